#include "hymm/dense/ScanPoints.h"

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hymm::dense
{
ScanPoints ScanPoints::fromRangeScan(
    const mrpt::obs::CObservation2DRangeScan& obs, double range_std_m, double bearing_std_rad)
{
    ScanPoints s;
    s.sensor_on_vehicle = mrpt::math::TPose2D(obs.sensorPose.x(), obs.sensorPose.y(), obs.sensorPose.yaw());
    s.range_std_m = range_std_m;
    s.bearing_std_rad = bearing_std_rad;
    const bool with_intensity = obs.hasIntensity();
    s.points.reserve(obs.getScanSize());
    s.range_bearing.reserve(obs.getScanSize());
    for (size_t i = 0; i < obs.getScanSize(); ++i)
    {
        const double a = obs.getScanAngle(i);
        if (!obs.getScanRangeValidity(i))
        {
            s.no_return_bearings.push_back(a);  // no echo: carries a bearing, no range
            continue;
        }
        const double r = obs.getScanRange(i);
        if (!(std::isfinite(r) && r > 0))
        {
            ++s.skipped;  // a failed reading, not evidence of free space
            continue;
        }
        s.points.emplace_back(r * std::cos(a), r * std::sin(a));
        s.range_bearing.emplace_back(r, a);
        if (with_intensity) s.values.push_back(static_cast<double>(obs.getScanIntensity(i)));
    }
    s.validate();
    return s;
}

Eigen::Vector2d ScanPoints::rangeBearing(size_t i) const
{
    if (!range_bearing.empty()) return range_bearing.at(i);
    const Eigen::Vector2d& p = points.at(i);
    return {p.norm(), std::atan2(p.y(), p.x())};
}

void ScanPoints::validate() const
{
    const auto fail = [](const std::string& what) {
        throw std::invalid_argument("ScanPoints: " + what);
    };
    if (!values.empty() && values.size() != points.size())
        fail("values has " + std::to_string(values.size()) + " entries for " +
             std::to_string(points.size()) + " returns (need 0 or one per return)");
    if (!range_bearing.empty() && range_bearing.size() != points.size())
        fail("range_bearing has " + std::to_string(range_bearing.size()) + " entries for " +
             std::to_string(points.size()) + " returns (need 0 or one per return)");
    if (!value_stds.empty() && value_stds.size() != values.size())
        fail("value_stds has " + std::to_string(value_stds.size()) + " entries for " +
             std::to_string(values.size()) + " values (need 0 or one per value)");
    for (size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i])) fail("value " + std::to_string(i) + " is not finite");
    for (size_t i = 0; i < value_stds.size(); ++i)
        if (!(std::isfinite(value_stds[i]) && value_stds[i] > 0))
            fail("value_std " + std::to_string(i) + "=" + std::to_string(value_stds[i]) +
                 " must be finite and > 0");
    if (!(range_std_m >= 0) || !std::isfinite(range_std_m))
        fail("range_std_m=" + std::to_string(range_std_m) + " must be >= 0 (0 = unknown)");
    if (!(bearing_std_rad >= 0) || !std::isfinite(bearing_std_rad))
        fail("bearing_std_rad=" + std::to_string(bearing_std_rad) + " must be >= 0 (0 = unknown)");
    for (size_t i = 0; i < no_return_bearings.size(); ++i)
        if (!std::isfinite(no_return_bearings[i]))
            fail("no-return bearing " + std::to_string(i) + " is not finite");
}

WorldScan ScanPoints::toWorld(
    const mrpt::math::TPose2D& vehicle_pose, double max_range_m, double no_return_free_range_m) const
{
    if (!(no_return_free_range_m >= 0))  // also rejects NaN
        throw std::invalid_argument(
            "ScanPoints::toWorld: no_return_free_range_m=" + std::to_string(no_return_free_range_m) +
            " must be >= 0 (0 = no-return beams give no free space)");
    const mrpt::math::TPose2D sensor = vehicle_pose + sensor_on_vehicle;
    const double c = std::cos(sensor.phi), s = std::sin(sensor.phi);
    const double no_return_range = std::min(no_return_free_range_m, max_range_m);
    const bool with_no_return = no_return_range > 0 && !no_return_bearings.empty();
    WorldScan w;
    w.sensor = Eigen::Vector2d(sensor.x, sensor.y);
    w.lo = w.hi = w.sensor;
    w.beams.reserve(points.size() + (with_no_return ? no_return_bearings.size() : 0));
    const auto place = [&](WorldBeam& b, const Eigen::Vector2d& q) {
        b.end = w.sensor + Eigen::Vector2d(c * q.x() - s * q.y(), s * q.x() + c * q.y());
        w.lo = w.lo.cwiseMin(b.end);
        w.hi = w.hi.cwiseMax(b.end);
        w.beams.push_back(b);
    };
    for (size_t i = 0; i < points.size(); ++i)
    {
        const Eigen::Vector2d& p = points[i];
        const double r = p.norm();
        if (!(r > 0)) continue;
        WorldBeam b;
        b.source = i;
        Eigen::Vector2d q = p;
        if (r > max_range_m)
        {
            q *= max_range_m / r;
            b.hit = false;
            ++w.beyond_range;
        }
        place(b, q);
    }
    if (!with_no_return) return w;
    for (size_t i = 0; i < no_return_bearings.size(); ++i)
    {
        WorldBeam b;
        b.hit = false;
        b.no_return = true;
        b.source = i;
        const double a = no_return_bearings[i];
        place(b, no_return_range * Eigen::Vector2d(std::cos(a), std::sin(a)));
        ++w.no_return;
    }
    return w;
}

}  // namespace hymm::dense
