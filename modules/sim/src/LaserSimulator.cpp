#include "hymm/sim/LaserSimulator.h"

#include <hymm/core/RangeBearingModel.h>
#include <hymm/core/config_utils.h>
#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

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

hymm::core::OptionTable LaserSimulator::Options::table()
{
    using namespace hymm::core;
    OptionTable t = commonTable();
    t.degrees("resolution_deg", resolution, above(0, 360), "angle between beams");
    t.flag("intensity", intensity,
           "report each return's surface property as its intensity (saved only when true)");
    t.real("std_intensity", std_intensity, "", between(0, 1e9),
           "intensity noise, 1 sigma, in intensity units (saved only with intensity = true)");
    return t;
}

void LaserSimulator::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                 const std::string& s)
{
    table().load(cfg, s);
    constexpr size_t kMaxBeams = 100000;  // guards against a resolution typed in radians
    if (beamCount() > kMaxBeams)
        hymm::core::throwConfigError(s, "resolution_deg",
                                     detail::formatNumber(mrpt::RAD2DEG(resolution)),
                                     "gives more than 100000 beams");
}

void LaserSimulator::Options::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                               const std::string& s) const
{
    // Only scenarios with intensities write their keys, so the others keep their saved text.
    auto copy = *this;
    detail::saveTable(cfg, s, copy.table(),
                      intensity ? std::vector<std::string>{} : std::vector<std::string>{"intensity", "std_intensity"});
}

LaserSimulator::LaserSimulator(const Options& options, uint32_t seed, uint32_t intensity_seed)
    : options_(options), rng_(seed), intensity_rng_(intensity_seed)
{
}

int32_t LaserSimulator::intensityOf(double property)
{
    double v = property;
    if (options_.std_intensity > 0)
        v += options_.std_intensity * intensity_rng_.drawGaussian1D_normalized();
    constexpr double kLo = std::numeric_limits<int32_t>::min();
    constexpr double kHi = std::numeric_limits<int32_t>::max();
    return static_cast<int32_t>(std::lround(std::clamp(v, kLo, kHi)));
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
    scan->setScanHasIntensity(o.intensity);

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
            if (o.intensity)
            {
                const Vec2 at = origin + hit->range * Vec2(std::cos(angle), std::sin(angle));
                scan->setScanIntensity(i, intensityOf(world.propertyAt(*hit, at)));
            }
        }
        else
        {
            scan->setScanRange(i, static_cast<float>(o.max_range_m));
            scan->setScanRangeValidity(i, false);
            if (o.intensity) scan->setScanIntensity(i, 0);
        }
    }
    return scan;
}

}  // namespace hymm::sim
