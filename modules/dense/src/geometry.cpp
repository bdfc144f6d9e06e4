#include "hymm/dense/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hymm::dense
{
namespace
{
double cross(const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); }
}  // namespace

std::optional<SegmentInterval> clipSegmentToTriangle(
    const Eigen::Vector2d& a, const Eigen::Vector2d& b,
    const std::array<Eigen::Vector2d, 3>& tri, double tol)
{
    // Cyrus-Beck: inside means on the interior side of all three edge lines. The
    // orientation sign makes the test work for clockwise triangles too.
    const double orient = cross(tri[1] - tri[0], tri[2] - tri[0]) >= 0 ? 1.0 : -1.0;
    const Eigen::Vector2d d = b - a;
    SegmentInterval iv;
    for (size_t i = 0; i < 3; ++i)
    {
        const Eigen::Vector2d& v = tri[i];
        const Eigen::Vector2d e = tri[(i + 1) % 3] - v;
        const double len = e.norm();
        if (len <= 0) return std::nullopt;
        // Signed distance of a + t d to the edge line: (num + t den) / len, >= -tol inside.
        const double num = orient * cross(e, a - v) + tol * len;
        const double den = orient * cross(e, d);
        if (den == 0)
        {
            if (num < 0) return std::nullopt;
            continue;
        }
        const double t = -num / den;
        if (den > 0)
            iv.t0 = std::max(iv.t0, t);
        else
            iv.t1 = std::min(iv.t1, t);
        if (iv.t0 > iv.t1) return std::nullopt;
    }
    return iv;
}

std::optional<SegmentInterval> clipSegmentToBox(
    const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& lo,
    const Eigen::Vector2d& hi)
{
    const Eigen::Vector2d d = b - a;
    SegmentInterval iv;
    for (int k = 0; k < 2; ++k)
    {
        if (d[k] == 0)
        {
            if (a[k] < lo[k] || a[k] > hi[k]) return std::nullopt;
            continue;
        }
        double ta = (lo[k] - a[k]) / d[k];
        double tb = (hi[k] - a[k]) / d[k];
        if (ta > tb) std::swap(ta, tb);
        iv.t0 = std::max(iv.t0, ta);
        iv.t1 = std::min(iv.t1, tb);
        if (iv.t0 > iv.t1) return std::nullopt;
    }
    return iv;
}

bool boxIntersectsTriangle(
    const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
    const std::array<Eigen::Vector2d, 3>& tri)
{
    for (int k = 0; k < 2; ++k)
    {
        const double mn = std::min({tri[0][k], tri[1][k], tri[2][k]});
        const double mx = std::max({tri[0][k], tri[1][k], tri[2][k]});
        if (mx < lo[k] || mn > hi[k]) return false;
    }
    const std::array<Eigen::Vector2d, 4> box{{lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}}};
    for (size_t i = 0; i < 3; ++i)
    {
        const Eigen::Vector2d e = tri[(i + 1) % 3] - tri[i];
        const Eigen::Vector2d n(-e.y(), e.x());
        const double t0 = n.dot(tri[0]), t1 = n.dot(tri[1]), t2 = n.dot(tri[2]);
        const double tmin = std::min({t0, t1, t2}), tmax = std::max({t0, t1, t2});
        double bmin = std::numeric_limits<double>::infinity(), bmax = -bmin;
        for (const auto& c : box)
        {
            bmin = std::min(bmin, n.dot(c));
            bmax = std::max(bmax, n.dot(c));
        }
        if (bmax < tmin || bmin > tmax) return false;
    }
    return true;
}

bool triangleContains(
    const std::array<Eigen::Vector2d, 3>& tri, const Eigen::Vector2d& p, double tol)
{
    const double orient = cross(tri[1] - tri[0], tri[2] - tri[0]) >= 0 ? 1.0 : -1.0;
    for (size_t i = 0; i < 3; ++i)
    {
        const Eigen::Vector2d e = tri[(i + 1) % 3] - tri[i];
        if (orient * cross(e, p - tri[i]) < -tol * e.norm()) return false;
    }
    return true;
}

double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
    const Eigen::Vector2d d = b - a;
    const double l2 = d.squaredNorm();
    const double t = l2 > 0 ? std::clamp((p - a).dot(d) / l2, 0.0, 1.0) : 0.0;
    return (a + t * d - p).norm();
}

}  // namespace hymm::dense
