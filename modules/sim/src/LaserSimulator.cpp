#include "hymm/sim/LaserSimulator.h"

#include <hymm/core/RangeBearingModel.h>
#include <hymm/core/config_utils.h>
#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <cmath>

#include "config_text.h"

namespace hymm::sim
{
LaserSimulator::Options::Options()
{
    sensor_label = "LASER";
    std_bearing = 0;
}

size_t LaserSimulator::Options::beamCount() const
{
    return static_cast<size_t>(std::lround(fov / resolution)) + 1;
}

void LaserSimulator::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                 const std::string& s)
{
    auto keys = commonKeys();
    keys.push_back("resolution_deg");
    hymm::core::checkKnownKeys(cfg, s, keys);
    loadCommon(cfg, s);
    resolution = mrpt::DEG2RAD(
        hymm::core::readDoubleMin(cfg, s, "resolution_deg", mrpt::RAD2DEG(resolution), 0.0, true));
    constexpr size_t kMaxBeams = 100000;  // guards against a resolution typed in radians
    if (beamCount() > kMaxBeams)
        hymm::core::throwConfigError(s, "resolution_deg",
                                     detail::formatNumber(mrpt::RAD2DEG(resolution)),
                                     "gives more than 100000 beams");
}

void LaserSimulator::Options::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                               const std::string& s) const
{
    saveCommon(cfg, s);
    detail::writeNumber(cfg, s, "resolution_deg", mrpt::RAD2DEG(resolution));
}

LaserSimulator::LaserSimulator(const Options& options, uint32_t seed)
    : options_(options), rng_(seed)
{
}

mrpt::obs::CObservation2DRangeScan::Ptr LaserSimulator::observe(const World& world,
                                                                const Eigen::Vector3d& vehicle_pose,
                                                                double t,
                                                                mrpt::Clock::time_point stamp)
{
    const auto& o = options_;
    auto scan = mrpt::obs::CObservation2DRangeScan::Create();
    scan->sensorLabel = o.sensor_label;
    scan->timestamp = stamp;
    scan->aperture = static_cast<float>(o.fov);
    scan->rightToLeft = true;
    scan->maxRange = static_cast<float>(o.max_range_m);
    scan->stdError = static_cast<float>(o.std_range_m);
    scan->beamAperture = static_cast<float>(o.resolution);
    scan->sensorPose = o.mountPose3D();
    scan->resizeScan(o.beamCount());

    const Eigen::Vector3d sensor = hymm::core::sensorGlobalPose(vehicle_pose, o.mountPose());
    const Vec2 origin(sensor[0], sensor[1]);
    const WorldSnapshot snap = world.snapshot(t, origin, o.max_range_m);
    for (size_t i = 0; i < scan->getScanSize(); ++i)
    {
        double angle = sensor[2] + scan->getScanAngle(i);
        if (o.std_bearing > 0) angle += o.std_bearing * rng_.drawGaussian1D_normalized();
        const auto hit = snap.castRay(origin, angle, o.max_range_m);
        if (hit)
        {
            const double r = hit->range + o.std_range_m * rng_.drawGaussian1D_normalized();
            scan->setScanRange(i, static_cast<float>(std::clamp(r, 0.0, o.max_range_m)));
            scan->setScanRangeValidity(i, true);
        }
        else
        {
            scan->setScanRange(i, static_cast<float>(o.max_range_m));
            scan->setScanRangeValidity(i, false);
        }
    }
    return scan;
}

}  // namespace hymm::sim
