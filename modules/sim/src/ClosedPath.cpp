#include "hymm/sim/ClosedPath.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hymm::sim
{
namespace
{
// Arcs are discretised into chords of at most this angle.
constexpr double kArcStepRad = 5.0 * M_PI / 180.0;
// Turns smaller than this are left as they are (no arc).
constexpr double kMinTurnRad = 1e-6;
// A corner turning more than this is a U-turn the path follower cannot drive.
constexpr double kMaxTurnRad = 175.0 * M_PI / 180.0;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

std::string pointText(const Vec2& p)
{
    return "(" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ")";
}

/** Appends the rounded corner at waypoint `p` between directions u1 (in) and u2 (out). */
void appendCorner(Polygon& out, const Vec2& p, const Vec2& u1, const Vec2& u2, double max_cut,
                  double radius)
{
    const double turn = std::atan2(cross(u1, u2), u1.dot(u2));
    if (std::abs(turn) > kMaxTurnRad)
        throw std::invalid_argument("path: waypoint " + pointText(p) + " is a U-turn");
    if (radius <= 0 || std::abs(turn) < kMinTurnRad)
    {
        out.push_back(p);
        return;
    }
    const double t = std::tan(std::abs(turn) / 2);
    const double cut = std::min(radius * t, max_cut);
    const double r = cut / t;
    const Vec2 t1 = p - cut * u1;
    const Vec2 n1(-u1.y(), u1.x());
    const Vec2 c = t1 + (turn > 0 ? r : -r) * n1;
    const double a0 = std::atan2(t1.y() - c.y(), t1.x() - c.x());
    const int m = std::max(1, static_cast<int>(std::ceil(std::abs(turn) / kArcStepRad)));
    for (int j = 0; j <= m; ++j)
    {
        const double a = a0 + turn * j / m;
        out.emplace_back(c.x() + r * std::cos(a), c.y() + r * std::sin(a));
    }
}
}  // namespace

ClosedPath::ClosedPath(const std::vector<Vec2>& wp, double corner_radius)
{
    const size_t n = wp.size();
    if (n < 3)
        throw std::invalid_argument("path: a closed loop needs at least 3 waypoints, got " +
                                    std::to_string(n));
    for (size_t i = 0; i < n; ++i)
        if ((wp[(i + 1) % n] - wp[i]).norm() < 1e-9)
            throw std::invalid_argument("path: waypoint " + pointText(wp[i]) + " is repeated");
    for (size_t i = 0; i < n; ++i)
    {
        const Vec2& prev = wp[(i + n - 1) % n];
        const Vec2& next = wp[(i + 1) % n];
        const double len_in = (wp[i] - prev).norm(), len_out = (next - wp[i]).norm();
        appendCorner(pts_, wp[i], (wp[i] - prev) / len_in, (next - wp[i]) / len_out,
                     0.5 * std::min(len_in, len_out), corner_radius);
    }
    cum_.assign(1, 0.0);
    for (size_t i = 0; i < pts_.size(); ++i)
        cum_.push_back(cum_.back() + (pts_[(i + 1) % pts_.size()] - pts_[i]).norm());
}

size_t ClosedPath::segmentAt(double s) const
{
    const auto it = std::upper_bound(cum_.begin(), cum_.end(), s);
    const size_t i = static_cast<size_t>(std::max<long>(0, (it - cum_.begin()) - 1));
    return std::min(i, pts_.size() - 1);
}

Vec2 ClosedPath::pointAt(double s) const
{
    const double L = length();
    s = std::fmod(s, L);
    if (s < 0) s += L;
    const size_t i = segmentAt(s);
    const Vec2& a = pts_[i];
    const Vec2& b = pts_[(i + 1) % pts_.size()];
    const double seg = cum_[i + 1] - cum_[i];
    return seg > 0 ? Vec2(a + (b - a) * ((s - cum_[i]) / seg)) : a;
}

double ClosedPath::headingAt(double s) const
{
    const double L = length();
    s = std::fmod(s, L);
    if (s < 0) s += L;
    const size_t i = segmentAt(s);
    const Vec2 d = pts_[(i + 1) % pts_.size()] - pts_[i];
    return std::atan2(d.y(), d.x());
}

double ClosedPath::project(const Vec2& p, double hint, double back, double ahead) const
{
    const double L = length();
    double best_s = hint, best_d = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < pts_.size(); ++i)
    {
        const Vec2& a = pts_[i];
        const Vec2 e = pts_[(i + 1) % pts_.size()] - a;
        const double l2 = e.squaredNorm();
        const double u = l2 > 0 ? std::clamp((p - a).dot(e) / l2, 0.0, 1.0) : 0.0;
        const double s_wrapped = cum_[i] + u * (cum_[i + 1] - cum_[i]);
        const double s = s_wrapped + L * std::round((hint - s_wrapped) / L);
        if (s < hint - back || s > hint + ahead) continue;
        const double d = (p - (a + u * e)).norm();
        if (d < best_d)
        {
            best_d = d;
            best_s = s;
        }
    }
    return best_s;
}

double ClosedPath::distanceTo(const Vec2& p) const
{
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < pts_.size(); ++i)
        best = std::min(best, pointSegmentDistance(p, pts_[i], pts_[(i + 1) % pts_.size()]));
    return best;
}

}  // namespace hymm::sim
