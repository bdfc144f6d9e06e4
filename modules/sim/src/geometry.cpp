#include "hymm/sim/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hymm::sim
{
namespace
{
// Rays parallel to a segment within this |sin| are treated as missing it.
constexpr double kParallelEps = 1e-12;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

bool segmentsCross(const Vec2& a0, const Vec2& a1, const Vec2& b0, const Vec2& b1)
{
    const double d1 = cross(a1 - a0, b0 - a0), d2 = cross(a1 - a0, b1 - a0);
    const double d3 = cross(b1 - b0, a0 - b0), d4 = cross(b1 - b0, a1 - b0);
    return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 &&
           d4 != 0;
}
}  // namespace

std::optional<double> rayCircle(const Vec2& o, const Vec2& d, const Vec2& c, double r)
{
    const Vec2 m = o - c;
    const double b = m.dot(d);
    const double disc = b * b - (m.squaredNorm() - r * r);
    if (disc < 0) return std::nullopt;
    const double sq = std::sqrt(disc);
    if (-b - sq >= 0) return -b - sq;  // from outside: the entry point
    if (-b + sq >= 0) return -b + sq;  // from inside: the exit point
    return std::nullopt;               // circle behind the ray
}

std::optional<double> raySegment(const Vec2& o, const Vec2& d, const Vec2& a, const Vec2& b)
{
    const Vec2 e = b - a;
    const double den = cross(d, e);
    if (std::abs(den) <= kParallelEps * e.norm()) return std::nullopt;
    const Vec2 w = a - o;
    const double t = cross(w, e) / den;
    const double u = cross(w, d) / den;
    if (t < 0 || u < 0 || u > 1) return std::nullopt;
    return t;
}

std::optional<double> rayPolygon(const Vec2& o, const Vec2& d, const Polygon& poly)
{
    std::optional<double> best;
    for (size_t i = 0, n = poly.size(); i < n; ++i)
    {
        const auto t = raySegment(o, d, poly[i], poly[(i + 1) % n]);
        if (t && (!best || *t < *best)) best = t;
    }
    return best;
}

bool pointInPolygon(const Vec2& p, const Polygon& poly)
{
    bool inside = false;
    for (size_t i = 0, n = poly.size(), j = n - 1; i < n; j = i++)
    {
        const Vec2 &a = poly[i], &b = poly[j];
        if ((a.y() > p.y()) != (b.y() > p.y()) &&
            p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
            inside = !inside;
    }
    return inside;
}

double pointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b)
{
    const Vec2 e = b - a;
    const double l2 = e.squaredNorm();
    if (l2 == 0) return (p - a).norm();
    const double u = std::clamp((p - a).dot(e) / l2, 0.0, 1.0);
    return (p - (a + u * e)).norm();
}

double pointPolygonDistance(const Vec2& p, const Polygon& poly)
{
    if (pointInPolygon(p, poly)) return 0.0;
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0, n = poly.size(); i < n; ++i)
        best = std::min(best, pointSegmentDistance(p, poly[i], poly[(i + 1) % n]));
    return best;
}

double segmentSegmentDistance(const Vec2& a0, const Vec2& a1, const Vec2& b0, const Vec2& b1)
{
    if (segmentsCross(a0, a1, b0, b1)) return 0.0;
    return std::min({pointSegmentDistance(a0, b0, b1), pointSegmentDistance(a1, b0, b1),
                     pointSegmentDistance(b0, a0, a1), pointSegmentDistance(b1, a0, a1)});
}

double boundaryDistance(const Polygon& a, const Polygon& b)
{
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0, na = a.size(); i < na; ++i)
        for (size_t j = 0, nb = b.size(); j < nb; ++j)
            best = std::min(best,
                            segmentSegmentDistance(a[i], a[(i + 1) % na], b[j], b[(j + 1) % nb]));
    return best;
}

double polygonDistance(const Polygon& a, const Polygon& b)
{
    if ((!b.empty() && pointInPolygon(b[0], a)) || (!a.empty() && pointInPolygon(a[0], b)))
        return 0.0;
    return boundaryDistance(a, b);
}

double signedArea(const Polygon& poly)
{
    double s = 0;
    for (size_t i = 0, n = poly.size(); i < n; ++i) s += cross(poly[i], poly[(i + 1) % n]);
    return 0.5 * s;
}

Polygon transformPolygon(const Polygon& local, double x, double y, double phi)
{
    const double c = std::cos(phi), s = std::sin(phi);
    Polygon out;
    out.reserve(local.size());
    for (const auto& p : local)
        out.emplace_back(x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y());
    return out;
}

void boundingCircle(const Polygon& poly, Vec2& centre, double& radius)
{
    centre = Vec2::Zero();
    for (const auto& p : poly) centre += p;
    if (!poly.empty()) centre /= static_cast<double>(poly.size());
    radius = 0;
    for (const auto& p : poly) radius = std::max(radius, (p - centre).norm());
}

}  // namespace hymm::sim
