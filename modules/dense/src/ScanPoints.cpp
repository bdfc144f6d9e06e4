#include "hymm/dense/ScanPoints.h"

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>

namespace hymm::dense
{
ScanPoints ScanPoints::fromRangeScan(const mrpt::obs::CObservation2DRangeScan& obs)
{
    ScanPoints s;
    s.sensor_on_vehicle = mrpt::math::TPose2D(obs.sensorPose.x(), obs.sensorPose.y(), obs.sensorPose.yaw());
    s.points.reserve(obs.getScanSize());
    for (size_t i = 0; i < obs.getScanSize(); ++i)
    {
        if (!obs.getScanRangeValidity(i)) continue;
        const double r = obs.getScanRange(i);
        const double a = obs.getScanAngle(i);
        s.points.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    return s;
}

WorldScan ScanPoints::toWorld(const mrpt::math::TPose2D& vehicle_pose, double max_range_m) const
{
    const mrpt::math::TPose2D sensor = vehicle_pose + sensor_on_vehicle;
    const double c = std::cos(sensor.phi), s = std::sin(sensor.phi);
    WorldScan w;
    w.sensor = Eigen::Vector2d(sensor.x, sensor.y);
    w.lo = w.hi = w.sensor;
    w.beams.reserve(points.size());
    for (const Eigen::Vector2d& p : points)
    {
        const double r = p.norm();
        if (!(r > 0)) continue;
        WorldBeam b;
        Eigen::Vector2d q = p;
        if (r > max_range_m)
        {
            q *= max_range_m / r;
            b.hit = false;
            ++w.beyond_range;
        }
        b.end = w.sensor + Eigen::Vector2d(c * q.x() - s * q.y(), s * q.x() + c * q.y());
        w.lo = w.lo.cwiseMin(b.end);
        w.hi = w.hi.cwiseMax(b.end);
        w.beams.push_back(b);
    }
    return w;
}

}  // namespace hymm::dense
