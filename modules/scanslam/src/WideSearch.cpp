/**
 * @file WideSearch.cpp
 * @brief Two-level correlative search over a wide window with an ambiguity test.
 */
#include "hymm/scanslam/WideSearch.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "LikelihoodGrid.h"

namespace hymm::scanslam
{
namespace
{
struct Pose
{
    Vec3 z;
    double score;
};

/** Upper bound of how far a template point of radius `r` moves between poses a and b. */
double poseDistance(const Vec3& a, const Vec3& b, double r)
{
    return (a.head<2>() - b.head<2>()).norm() + r * std::abs(mrpt::math::wrapToPi(a.z() - b.z()));
}

std::vector<Vec2> subsample(const std::vector<Vec2>& pts, size_t n)
{
    if (pts.size() <= n) return pts;
    std::vector<Vec2> out;
    out.reserve(n);
    for (size_t k = 0; k < n; ++k) out.push_back(pts[k * pts.size() / n]);
    return out;
}

/** The scan's returns with points added every `step` along the gaps between consecutive
 *  returns closer than `max_gap`: the likelihood then follows the surface, not the beam
 *  spacing (sparse at grazing incidence), so a template sliding along a face or
 *  meeting another sampling scores by shape alone. */
PointSet densify(const PointSet& scan, double step, double max_gap)
{
    PointSet out;
    for (size_t i = 0; i < scan.size(); ++i)
    {
        out.points.push_back(scan.points[i]);
        if (i + 1 == scan.size()) break;
        const Vec2 d = scan.points[i + 1] - scan.points[i];
        const double len = d.norm();
        if (len >= max_gap) continue;
        const int n = static_cast<int>(len / step);
        for (int k = 1; k <= n; ++k) out.points.push_back(scan.points[i] + d * (k / (n + 1.0)));
    }
    return out;
}

/** Level A: every pose of the window on the coarse grid; the local maxima (26-
 *  neighbourhood), best first. */
std::vector<Pose> levelA(const LikelihoodGrid& g, const std::vector<Vec2>& pts, const Vec3& z0,
                         const Vec3& half, double step, double dphi, size_t& poses)
{
    const int nx = static_cast<int>(std::ceil(half.x() / step)), ny = static_cast<int>(std::ceil(half.y() / step));
    const int na = static_cast<int>(std::ceil(half.z() / dphi));
    const int sx = 2 * nx + 1, sy = 2 * ny + 1, sa = 2 * na + 1;
    std::vector<double> s(static_cast<size_t>(sx) * static_cast<size_t>(sy) * static_cast<size_t>(sa));
    auto idx = [&](int a, int y, int x) {
        return (static_cast<size_t>(a) * static_cast<size_t>(sy) + static_cast<size_t>(y)) * static_cast<size_t>(sx) +
               static_cast<size_t>(x);
    };
    std::vector<double> scores;
    for (int a = 0; a < sa; ++a)
    {
        const Mat2 r = rotation(z0.z() + (a - na) * dphi);
        std::vector<Vec2> rot;
        rot.reserve(pts.size());
        for (const Vec2& p : pts) rot.push_back(r * p);
        g.scoreLattice(rot, z0.x(), z0.y(), step, nx, ny, scores);
        std::copy(scores.begin(), scores.end(), s.begin() + static_cast<std::ptrdiff_t>(idx(a, 0, 0)));
    }
    poses += s.size();
    std::vector<Pose> peaks;
    for (int a = 0; a < sa; ++a)
        for (int y = 0; y < sy; ++y)
            for (int x = 0; x < sx; ++x)
            {
                const double v = s[idx(a, y, x)];
                bool peak = true;
                for (int da = -1; da <= 1 && peak; ++da)
                    for (int dy = -1; dy <= 1 && peak; ++dy)
                        for (int dx = -1; dx <= 1 && peak; ++dx)
                        {
                            const int aa = a + da, yy = y + dy, xx = x + dx;
                            if ((da || dy || dx) && aa >= 0 && aa < sa && yy >= 0 && yy < sy && xx >= 0 && xx < sx)
                                peak = s[idx(aa, yy, xx)] <= v;
                        }
                if (peak)
                    peaks.push_back({Vec3(z0.x() + (x - nx) * step, z0.y() + (y - ny) * step, z0.z() + (a - na) * dphi), v});
            }
    std::sort(peaks.begin(), peaks.end(), [](const Pose& p, const Pose& q) { return p.score > q.score; });
    return peaks;
}

/** Level B: exhaustive search +-one level-A step (and angle step) around `c`. */
Pose levelB(const LikelihoodGrid& g, const std::vector<Vec2>& pts, const Vec3& c, double stepA, double dphiA,
            double step, double dphi, size_t& poses)
{
    const int n = static_cast<int>(std::ceil(stepA / step)), na = static_cast<int>(std::ceil(dphiA / dphi));
    Pose best{c, -std::numeric_limits<double>::infinity()};
    std::vector<double> scores;
    for (int a = -na; a <= na; ++a)
    {
        const Mat2 r = rotation(c.z() + a * dphi);
        std::vector<Vec2> rot;
        rot.reserve(pts.size());
        for (const Vec2& p : pts) rot.push_back(r * p);
        g.scoreLattice(rot, c.x(), c.y(), step, n, n, scores);
        const double* sc = scores.data();
        for (int y = -n; y <= n; ++y)
            for (int x = -n; x <= n; ++x, ++sc)
            {
                const double v = *sc;
                ++poses;
                if (v > best.score) best = {Vec3(c.x() + x * step, c.y() + y * step, c.z() + a * dphi), v};
            }
    }
    return best;
}

/** Mean point likelihood (0 beyond the gate) and the share of points within the gate. */
std::pair<double, double> goodness(const LikelihoodGrid& g, const std::vector<Vec2>& pts, const Vec3& z)
{
    double sum = 0;
    size_t matched = 0;
    for (const Vec2& p : pts)
    {
        const Vec2 q = transformPoint(z, p);
        const double v = g.at(q.x(), q.y());
        if (v > g.floorValue() + 1e-9) sum += std::exp(v), ++matched;
    }
    const double n = static_cast<double>(std::max<size_t>(pts.size(), 1));
    return {sum / n, static_cast<double>(matched) / n};
}
/** The best separate level-A peaks (two level-A steps apart) refined at level B, then
 *  once more at a quarter of its step (separate peaks are compared at the same, fine,
 *  accuracy); their score: the goodness over all template points. */
std::vector<Pose> refinePeaks(const std::vector<Pose>& peaks, const LikelihoodGrid& gb, const std::vector<Vec2>& pts,
                              const std::vector<Vec2>& all, double radius, const WideSearchOptions& o, size_t& poses)
{
    const double dphiA = o.coarse_step_m / radius, dphiB = o.fine_step_m / radius;
    std::vector<Pose> refined;
    std::vector<Vec3> taken;
    for (const Pose& p : peaks)
    {
        if (static_cast<int>(taken.size()) >= o.candidates) break;
        if (std::any_of(taken.begin(), taken.end(),
                        [&](const Vec3& t) { return poseDistance(t, p.z, radius) < 2 * o.coarse_step_m; }))
            continue;
        taken.push_back(p.z);
        Pose b = levelB(gb, pts, p.z, o.coarse_step_m, dphiA, o.fine_step_m, dphiB, poses);
        b = levelB(gb, pts, b.z, o.fine_step_m, dphiB, 0.25 * o.fine_step_m, 0.25 * dphiB, poses);
        b.score = goodness(gb, all, b.z).first;
        refined.push_back(b);
    }
    std::sort(refined.begin(), refined.end(), [](const Pose& p, const Pose& q) { return p.score > q.score; });
    return refined;
}
}  // namespace

WideResult wideSearch(const PointSet& tpl, const PointSet& scan, const Vec3& z0, const Vec3& half,
                      const WideSearchOptions& o)
{
    WideResult res;
    res.z = z0;
    if (tpl.size() < 3 || scan.size() < 3 || !z0.allFinite() || !half.allFinite())
    {
        res.failure = "empty";
        return res;
    }
    double radius = 0.5;
    for (const Vec2& p : tpl.points) radius = std::max(radius, p.norm());
    // Grids over the window (plus the template's reach) clipped to the scan's extent.
    Vec2 slo = scan.points.front(), shi = slo;
    for (const Vec2& q : scan.points) slo = slo.cwiseMin(q), shi = shi.cwiseMax(q);
    const double reach = o.gate_sigma * o.coarse_step_m + 1.0;
    const Vec2 lo = (z0.head<2>() - half.head<2>() - Vec2::Constant(radius + reach)).cwiseMax(slo - Vec2::Constant(reach));
    const Vec2 hi = (z0.head<2>() + half.head<2>() + Vec2::Constant(radius + reach)).cwiseMin(shi + Vec2::Constant(reach));
    if ((hi - lo).minCoeff() <= 0)
    {
        res.failure = "no_overlap";
        return res;
    }
    const PointSet surface = densify(scan, 0.5 * o.fine_step_m, o.max_gap_m);
    const LikelihoodGrid ga(lo, hi, 0.5 * o.coarse_step_m, o.coarse_step_m, o.gate_sigma, scan);
    const LikelihoodGrid gb(lo, hi, 0.5 * o.fine_step_m, o.fine_sigma_m, o.gate_sigma, surface);
    const auto pts = subsample(tpl.points, o.max_points);
    const auto peaks = levelA(ga, pts, z0, half, o.coarse_step_m, o.coarse_step_m / radius, res.poses);
    const auto refined = refinePeaks(peaks, gb, pts, tpl.points, radius, o, res.poses);
    if (refined.empty())
    {
        res.failure = "no_overlap";
        return res;
    }
    res.z = refined.front().z;
    res.z.z() = mrpt::math::wrapToPi(res.z.z());
    const auto [g, matched] = goodness(gb, tpl.points, res.z);
    res.goodness = g;
    res.matched_fraction = matched;
    for (size_t k = 1; k < refined.size(); ++k)
        if (poseDistance(refined[k].z, refined.front().z, radius) > o.peak_separation_m)
        {
            res.second = refined[k].score;
            break;
        }
    if (matched < o.min_matched_fraction)
        res.failure = "no_overlap";
    else if (res.second >= o.max_ambiguity * res.goodness)
        res.failure = "ambiguous";
    else
        res.ok = true;
    return res;
}

namespace
{
/** The nearest return per bearing bin over the full circle (+inf: no return). */
class FirstHits
{
public:
    FirstHits(const std::vector<Vec2>& pts, double bin_rad)
        : bin_(bin_rad), r_(static_cast<size_t>(std::ceil(2 * M_PI / bin_rad)), kNone)
    {
        for (const Vec2& p : pts)
        {
            double& r = r_[index(std::atan2(p.y(), p.x()))];
            r = std::min(r, p.norm());
        }
    }
    /** How far the scan saw free space on `bearing`: the nearest return of its bin and
     *  both neighbours (+inf when any of them has none). */
    double freeUpTo(double bearing) const
    {
        const size_t n = r_.size(), i = index(bearing);
        const double here = r_[i], next = r_[(i + 1) % n], prev = r_[(i + n - 1) % n];
        return std::max({here, next, prev}) == kNone ? kNone : std::min({here, next, prev});
    }

private:
    static constexpr double kNone = std::numeric_limits<double>::infinity();
    size_t index(double bearing) const
    {
        const double u = (mrpt::math::wrapToPi(bearing) + M_PI) / bin_;
        return std::min(static_cast<size_t>(std::max(u, 0.0)), r_.size() - 1);
    }
    double bin_;
    std::vector<double> r_;
};

/** Counts the returns `pts` (frame at `pose` in the hits' frame) tested against and
 *  inside the free space of `hits`. */
void countConflicts(const FirstHits& hits, const std::vector<Vec2>& pts, const Vec3& pose, double margin,
                    size_t& tested, size_t& conflicts)
{
    for (const Vec2& q : transformedPoints(pts, pose))
    {
        const double free = hits.freeUpTo(std::atan2(q.y(), q.x()));
        if (!std::isfinite(free)) continue;
        ++tested;
        if (q.norm() < free - margin) ++conflicts;
    }
}
}  // namespace

double FreeSpaceConflict::share(size_t min_tested) const
{
    double out = 0;
    if (tested_ab >= std::max<size_t>(min_tested, 1)) out = double(conflicts_ab) / double(tested_ab);
    if (tested_ba >= std::max<size_t>(min_tested, 1)) out = std::max(out, double(conflicts_ba) / double(tested_ba));
    return out;
}

FreeSpaceConflict freeSpaceConflict(const std::vector<Vec2>& a, const std::vector<Vec2>& b, const Vec3& b_in_a,
                                    double margin_m, double bin_rad)
{
    FreeSpaceConflict out;
    if (!(bin_rad > 0) || !b_in_a.allFinite()) return out;
    countConflicts(FirstHits(a, bin_rad), b, b_in_a, margin_m, out.tested_ab, out.conflicts_ab);
    countConflicts(FirstHits(b, bin_rad), a, inverse(b_in_a), margin_m, out.tested_ba, out.conflicts_ba);
    return out;
}

}  // namespace hymm::scanslam
