#include "hymm/sim/LandmarkDetector.h"

#include <hymm/core/RangeBearingModel.h>
#include <hymm/core/config_utils.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>

#include "config_text.h"

namespace hymm::sim
{
LandmarkDetector::Options::Options() { sensor_label = "LANDMARKS"; }

hymm::core::OptionTable LandmarkDetector::Options::table()
{
    using namespace hymm::core;
    OptionTable t = commonTable();
    t.real("min_range_m", min_range_m, "m", between(0, 1e4), "closer landmarks are not reported");
    t.flag("known_ids", known_ids, "report the true landmark id (else -1)");
    t.flag("occlusion", occlusion, "objects and trunks hide what is behind them");
    return t;
}

void LandmarkDetector::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                   const std::string& s)
{
    table().load(cfg, s);
    if (min_range_m >= max_range_m)
        hymm::core::throwConfigError(s, "min_range_m", detail::formatNumber(min_range_m),
                                     "must be below max_range_m");
}

void LandmarkDetector::Options::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                                 const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

LandmarkDetector::LandmarkDetector(const Options& options, uint32_t seed)
    : options_(options), rng_(seed)
{
}

mrpt::obs::CObservationBearingRange::Ptr LandmarkDetector::observe(
    const World& world, const Eigen::Vector3d& vehicle_pose, double t,
    mrpt::Clock::time_point stamp)
{
    const auto& o = options_;
    auto obs = mrpt::obs::CObservationBearingRange::Create();
    obs->sensorLabel = o.sensor_label;
    obs->timestamp = stamp;
    obs->minSensorDistance = static_cast<float>(o.min_range_m);
    obs->maxSensorDistance = static_cast<float>(o.max_range_m);
    obs->fieldOfView_yaw = static_cast<float>(o.fov);
    obs->fieldOfView_pitch = 0;
    obs->setSensorPose(o.mountPose3D());
    obs->validCovariances = false;  // all readings share sensor_std_*
    obs->sensor_std_range = static_cast<float>(o.std_range_m);
    obs->sensor_std_yaw = static_cast<float>(o.std_bearing);
    obs->sensor_std_pitch = 0;

    const Eigen::Vector3d mount = o.mountPose();
    const Eigen::Vector3d sensor = hymm::core::sensorGlobalPose(vehicle_pose, mount);
    const Vec2 origin(sensor[0], sensor[1]);
    const WorldSnapshot snap = world.snapshot(t, origin, o.max_range_m);
    for (const auto& lm : snap.landmarks)
    {
        if ((lm.position - origin).norm() <= lm.radius) continue;  // sensor inside the trunk
        const Eigen::Vector2d z = hymm::core::observeRangeBearing(vehicle_pose, mount, lm.position);
        if (z[0] < o.min_range_m || z[0] > o.max_range_m || std::abs(z[1]) > o.fov / 2) continue;
        if (o.occlusion && snap.castRay(origin, sensor[2] + z[1], z[0] - lm.radius, lm.id))
            continue;
        mrpt::obs::CObservationBearingRange::TMeasurement m;
        m.range = static_cast<float>(z[0] + o.std_range_m * rng_.drawGaussian1D_normalized());
        m.yaw = static_cast<float>(
            mrpt::math::wrapToPi(z[1] + o.std_bearing * rng_.drawGaussian1D_normalized()));
        m.pitch = 0;
        m.landmarkID = o.known_ids ? static_cast<int32_t>(lm.id) : -1;
        m.covariance.setZero();
        m.covariance(0, 0) = o.std_range_m * o.std_range_m;
        m.covariance(1, 1) = o.std_bearing * o.std_bearing;
        obs->sensedData.push_back(m);
    }
    return obs;
}

}  // namespace hymm::sim
