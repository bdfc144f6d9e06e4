/**
 * @file ScanTemplate.cpp
 * @brief Landmark templates in their local frame (thesis 5.2.3) and the in-view test.
 */
#include "hymm/scanslam/ScanTemplate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>
#include <stdexcept>

namespace hymm::scanslam
{
ScanTemplate ScanTemplate::fromPoints(const PointSet& points)
{
    if (points.empty()) throw std::invalid_argument("ScanTemplate: no points");
    Vec2 c = Vec2::Zero();
    for (const Vec2& p : points.points) c += p;
    c /= static_cast<double>(points.size());
    ScanTemplate t;
    // Thesis Fig. 5.3: origin at the centroid, orientation the sensor's heading, so
    // only a translation separates the two frames and covariances keep their axes.
    t.frame_in_sensor = Vec3(c.x(), c.y(), 0.0);
    t.sog.points.reserve(points.size());
    t.sog.covs = points.covs;
    for (const Vec2& p : points.points) t.sog.points.push_back(p - c);
    return t;
}

ScanTemplate ScanTemplate::fromSegment(const PointSet& scan, const Segmenter::Segment& segment)
{
    PointSet pts;
    for (size_t i : segment) pts.add(scan.points.at(i), scan.covs.at(i));
    return fromPoints(pts);
}

double fractionInView(const ScanTemplate& tpl, const Vec3& z, double max_range_m, double fov)
{
    if (tpl.sog.empty()) return 0.0;
    size_t inside = 0;
    for (const Vec2& p : tpl.sog.points)
    {
        const Vec2 q = transformPoint(z, p);
        if (q.norm() < max_range_m && std::abs(std::atan2(q.y(), q.x())) <= 0.5 * fov) ++inside;
    }
    return static_cast<double>(inside) / static_cast<double>(tpl.sog.size());
}

PointSet visiblePart(const PointSet& tpl, const Vec3& z, double max_range_m, double fov,
                     double bin_rad, double depth_tol_m)
{
    PointSet out;
    if (tpl.empty() || !(bin_rad > 0)) return out;
    const size_t bins = static_cast<size_t>(std::ceil(2 * M_PI / bin_rad)) + 1;
    std::vector<double> nearest(bins, std::numeric_limits<double>::infinity());
    std::vector<double> r(tpl.size()), b(tpl.size());
    auto binOf = [&](double bearing) {
        return std::min(bins - 1, static_cast<size_t>((bearing + M_PI) / bin_rad));
    };
    for (size_t i = 0; i < tpl.size(); ++i)
    {
        const Vec2 q = transformPoint(z, tpl.points[i]);
        r[i] = q.norm();
        b[i] = std::atan2(q.y(), q.x());
        if (r[i] < max_range_m && std::abs(b[i]) <= 0.5 * fov)
            nearest[binOf(b[i])] = std::min(nearest[binOf(b[i])], r[i]);
    }
    for (size_t i = 0; i < tpl.size(); ++i)
        if (r[i] < max_range_m && std::abs(b[i]) <= 0.5 * fov && r[i] <= nearest[binOf(b[i])] + depth_tol_m)
            out.add(tpl.points[i], tpl.covs[i]);
    return out;
}

double templateRadius(const ScanTemplate& tpl)
{
    double r = 0;
    for (const Vec2& p : tpl.sog.points) r = std::max(r, p.norm());
    return r;
}

}  // namespace hymm::scanslam
