/**
 * @file laser_coverage.cpp
 * @brief The outline part the laser saw, and a point set's coverage of it (see the header).
 */
#include "hymm/eval/laser_coverage.h"

#include <hymm/ltr/AffineRegionMap.h>
#include <mrpt/math/KDTreeCapable.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>
#include <tuple>

namespace hymm::eval
{
namespace
{
/** Points of a std::vector indexed by MRPT's KD-tree (nanoflann) in double precision. */
class PointIndex : public mrpt::math::KDTreeCapable<PointIndex, double>
{
public:
    explicit PointIndex(const std::vector<Eigen::Vector2d>& pts) : pts_(pts) {}

    /** True if a point lies strictly closer than r to q. */
    bool anyWithin(const Eigen::Vector2d& q, double r) const
    {
        if (pts_.empty()) return false;
        return kdTreeRadiusSearch2D(q.x(), q.y(), r * r, found_) > 0;
    }

    // nanoflann dataset interface (via KDTreeCapable)
    size_t kdtree_get_point_count() const { return pts_.size(); }
    double kdtree_get_pt(size_t i, int dim) const { return pts_[i][dim]; }
    template <class BBOX>
    bool kdtree_get_bbox(BBOX&) const
    {
        return false;
    }

private:
    const std::vector<Eigen::Vector2d>& pts_;
    mutable std::vector<nanoflann::ResultItem<size_t, double>> found_;
};

/** Index of the true pose nearest in time to t within tol (truth sorted by t), or -1. */
long nearestInTime(const std::vector<io::StampedPose2D>& truth, double t, double tol)
{
    const auto it =
        std::lower_bound(truth.begin(), truth.end(), t,
                         [](const io::StampedPose2D& p, double v) { return p.t < v; });
    long best = -1;
    double best_dt = tol;
    const auto consider = [&](std::vector<io::StampedPose2D>::const_iterator c)
    {
        const double dt = std::abs(c->t - t);
        if (dt <= best_dt) best = static_cast<long>(c - truth.begin()), best_dt = dt;
    };
    if (it != truth.end()) consider(it);
    if (it != truth.begin()) consider(std::prev(it));
    return best;
}
}  // namespace

void LaserCoverageOptions::validate() const
{
    const auto positive = [](const char* key, double v)
    {
        if (!(v > 0))
            throw std::invalid_argument(std::string("LaserCoverageOptions: ") + key + "=" +
                                        std::to_string(v) + " must be > 0");
    };
    positive("sample_step_m", sample_step_m);
    positive("radius_m", radius_m);
    positive("max_range_m", max_range_m);
    positive("time_tolerance_s", time_tolerance_s);
}

OutlineSamples sampleOutlines(const std::vector<dense::Polygon>& outlines, double step_m,
                              bool closed)
{
    if (!(step_m > 0))
        throw std::invalid_argument("sampleOutlines: step_m=" + std::to_string(step_m) +
                                    " must be > 0");
    OutlineSamples out;
    for (size_t o = 0; o < outlines.size(); ++o)
    {
        const dense::Polygon& poly = outlines[o];
        const size_t n = poly.size();
        if (n < 2) continue;
        const size_t edges = closed && n > 2 ? n : n - 1;
        for (size_t i = 0; i < edges; ++i)
        {
            const Eigen::Vector2d a = poly[i], b = poly[(i + 1) % n];
            const double len = (b - a).norm();
            const auto k_end = static_cast<size_t>(std::ceil(len / step_m - 1e-9));
            for (size_t k = 0; k < k_end; ++k)
            {
                out.points.push_back(a + (b - a) * (static_cast<double>(k) * step_m / len));
                out.outline.push_back(o);
            }
        }
        if (!closed)
        {
            out.points.push_back(poly.back());
            out.outline.push_back(o);
        }
    }
    return out;
}

PlacedReturns placeAtTruePoses(const std::vector<TimedScan>& scans,
                               const std::vector<io::StampedPose2D>& true_path,
                               const LaserCoverageOptions& options)
{
    options.validate();
    if (true_path.empty()) throw std::invalid_argument("placeAtTruePoses: the true path is empty");
    std::vector<io::StampedPose2D> truth = true_path;
    std::stable_sort(truth.begin(), truth.end(),
                     [](const io::StampedPose2D& a, const io::StampedPose2D& b)
                     { return a.t < b.t; });
    PlacedReturns out;
    for (const TimedScan& s : scans)
    {
        const long k = nearestInTime(truth, s.t, options.time_tolerance_s);
        if (k < 0)
        {
            ++out.scans_unmatched;
            continue;
        }
        const auto& p = truth[static_cast<size_t>(k)];
        const dense::WorldScan w =
            s.scan.toWorld(mrpt::math::TPose2D(p.x, p.y, p.phi), options.max_range_m);
        for (const auto& b : w.beams)
            if (b.hit) out.points.push_back(b.end);
        out.beyond_range += w.beyond_range;
        ++out.scans_placed;
    }
    return out;
}

double SeenOutline::seenFraction() const
{
    return samples.points.empty()
               ? 0.0
               : static_cast<double>(seen_samples) / static_cast<double>(samples.points.size());
}

SeenOutline laserSeenOutline(const std::vector<TimedScan>& scans,
                             const std::vector<io::StampedPose2D>& true_path,
                             const std::vector<dense::Polygon>& outlines,
                             const LaserCoverageOptions& options)
{
    options.validate();
    SeenOutline out;
    out.radius_m = options.radius_m;
    out.samples = sampleOutlines(outlines, options.sample_step_m, options.closed);
    if (out.samples.points.empty())
        throw std::invalid_argument("laserSeenOutline: no outline segment");
    out.returns = placeAtTruePoses(scans, true_path, options);
    const PointIndex index(out.returns.points);
    out.seen.resize(out.samples.points.size(), 0);
    for (size_t i = 0; i < out.samples.points.size(); ++i)
        if (index.anyWithin(out.samples.points[i], options.radius_m))
        {
            out.seen[i] = 1;
            ++out.seen_samples;
        }
    return out;
}

SeenCoverage coverageOfSeen(const SeenOutline& seen, const std::vector<Eigen::Vector2d>& points)
{
    if (!(seen.radius_m > 0))
        throw std::invalid_argument("coverageOfSeen: the seen outline has no radius");
    SeenCoverage c;
    const PointIndex index(points);
    c.samples = seen.samples.points.size();
    c.covered.resize(c.samples, 0);
    for (size_t i = 0; i < c.samples; ++i)
    {
        const bool cov = index.anyWithin(seen.samples.points[i], seen.radius_m);
        c.covered[i] = cov ? 1 : 0;
        c.covered_samples += cov;
        if (seen.seen[i])
        {
            ++c.seen_samples;
            c.covered_seen_samples += cov;
        }
    }
    c.coverage =
        c.samples ? static_cast<double>(c.covered_samples) / static_cast<double>(c.samples) : 0.0;
    c.seen_coverage = c.seen_samples ? static_cast<double>(c.covered_seen_samples) /
                                           static_cast<double>(c.seen_samples)
                                     : 0.0;
    return c;
}

std::map<long, Eigen::Vector2d> trueRegionVertices(const ltr::RegionPartition& partition,
                                                   const std::map<long, Eigen::Vector2d>& landmarks)
{
    std::map<long, Eigen::Vector2d> out;
    const std::vector<long> ids = partition.regionIds();  // ascending: creation order
    for (long rid : ids)
        for (long v : partition.region(rid).vertex_ids)
            if (const auto it = landmarks.find(v); it != landmarks.end()) out[v] = it->second;
    for (long rid : ids)
    {
        const ltr::Region& r = partition.region(rid);
        std::vector<size_t> known, unknown;
        for (size_t k = 0; k < 3; ++k)
            (landmarks.count(r.vertex_ids[k]) ? known : unknown).push_back(k);
        if (unknown.size() != 1 || out.count(r.vertex_ids[unknown[0]])) continue;
        // The apex in the frame of its edge (midpoint, unit direction, its normal).
        const auto edgeFrame = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b)
        {
            const Eigen::Vector2d u = (b - a).normalized();
            return std::make_tuple(Eigen::Vector2d(0.5 * (a + b)), u,
                                   Eigen::Vector2d(-u.y(), u.x()));
        };
        const Eigen::Vector2d &ea = r.current[known[0]], &eb = r.current[known[1]];
        if (!((eb - ea).norm() > 0)) continue;
        const auto [m, u, n] = edgeFrame(ea, eb);
        const Eigen::Vector2d d = r.current[unknown[0]] - m;
        const auto [tm, tu, tn] =
            edgeFrame(out.at(r.vertex_ids[known[0]]), out.at(r.vertex_ids[known[1]]));
        out[r.vertex_ids[unknown[0]]] = tm + d.dot(u) * tu + d.dot(n) * tn;
    }
    return out;
}

LandmarkFramePoints pointsAtTrueVertices(const dense::HybridMetricMap& map,
                                         const ltr::RegionPartition& partition,
                                         const std::map<long, Eigen::Vector2d>& vertices)
{
    LandmarkFramePoints out;
    for (long rid : partition.regionIds())
    {
        const dense::LocalDenseMap* local = map.localMap(rid);
        const auto* layer =
            local ? local->layerAs<dense::PointsLayer>(dense::PointsLayer::kKind) : nullptr;
        if (!layer) continue;
        const auto& xs = layer->points().getPointsBufferRef_x();
        const auto& ys = layer->points().getPointsBufferRef_y();
        const ltr::Region& r = partition.region(rid);
        ltr::TriangleFrame::Vertices truth;
        bool known = true;
        for (size_t k = 0; k < 3; ++k)
        {
            const auto it = vertices.find(r.vertex_ids[k]);
            known = known && it != vertices.end();
            if (known) truth[k] = it->second;
        }
        const auto true_frame = known ? ltr::TriangleFrame::tryCreate(truth) : std::nullopt;
        if (!true_frame)
        {
            ++out.regions_skipped;
            out.points_skipped += xs.size();
            continue;
        }
        const ltr::AffineRegionMap to_true(ltr::TriangleFrame(r.reference), *true_frame);
        for (size_t i = 0; i < xs.size(); ++i)
            out.points.push_back(to_true.mapPoint(Eigen::Vector2d(xs[i], ys[i])));
        ++out.regions_drawn;
    }
    return out;
}

}  // namespace hymm::eval
