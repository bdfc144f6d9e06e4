/**
 * @file ScanTemplate.cpp
 * @brief Landmark templates in their local frame (thesis 5.2.3) and the in-view test.
 */
#include "hymm/scanslam/ScanTemplate.h"

#include <cmath>
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

}  // namespace hymm::scanslam
