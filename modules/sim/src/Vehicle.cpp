#include "hymm/sim/Vehicle.h"

#include <hymm/core/config_utils.h>
#include <mrpt/core/bits_math.h>

#include <cmath>

#include "config_text.h"

namespace hymm::sim
{
using hymm::core::readDoubleMin;

hymm::core::UteParams Vehicle::Options::ute() const
{
    hymm::core::UteParams p;
    p.L = wheelbase_m;
    p.H = encoder_offset_m;
    p.a = offset_a_m;
    p.b = offset_b_m;
    return p;
}

void Vehicle::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                          const std::string& s)
{
    hymm::core::checkKnownKeys(
        cfg, s,
        {"wheelbase_m", "encoder_offset_m", "offset_a_m", "offset_b_m", "speed_mps",
         "max_steering_deg", "std_speed_mps", "std_steering_deg"});
    wheelbase_m = readDoubleMin(cfg, s, "wheelbase_m", wheelbase_m, 0.0, true);
    encoder_offset_m = hymm::core::readDouble(cfg, s, "encoder_offset_m", encoder_offset_m);
    offset_a_m = hymm::core::readDouble(cfg, s, "offset_a_m", offset_a_m);
    offset_b_m = hymm::core::readDouble(cfg, s, "offset_b_m", offset_b_m);
    speed_mps = readDoubleMin(cfg, s, "speed_mps", speed_mps, 0.0, false);
    max_steering = mrpt::DEG2RAD(
        readDoubleMin(cfg, s, "max_steering_deg", mrpt::RAD2DEG(max_steering), 0.0, true));
    std_speed_mps = readDoubleMin(cfg, s, "std_speed_mps", std_speed_mps, 0.0, false);
    std_steering = mrpt::DEG2RAD(
        readDoubleMin(cfg, s, "std_steering_deg", mrpt::RAD2DEG(std_steering), 0.0, false));
    // Eq. A.3 needs 1 - tan(alpha) H / L away from zero; leave room for the noise too.
    constexpr double kSteeringNoiseSigmas = 6.0;
    const double worst = max_steering + kSteeringNoiseSigmas * std_steering;
    if (worst >= M_PI / 2 || std::tan(worst) * std::abs(encoder_offset_m) / wheelbase_m >= 0.99)
        hymm::core::throwConfigError(
            s, "max_steering_deg", detail::formatNumber(mrpt::RAD2DEG(max_steering)),
            "too large for the UTE model (Eq. A.3) with H=" +
                detail::formatNumber(encoder_offset_m) +
                ", L=" + detail::formatNumber(wheelbase_m) + " and 6 sigma of steering noise");
}

void Vehicle::Options::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                        const std::string& s) const
{
    detail::writeNumber(cfg, s, "wheelbase_m", wheelbase_m);
    detail::writeNumber(cfg, s, "encoder_offset_m", encoder_offset_m);
    detail::writeNumber(cfg, s, "offset_a_m", offset_a_m);
    detail::writeNumber(cfg, s, "offset_b_m", offset_b_m);
    detail::writeNumber(cfg, s, "speed_mps", speed_mps);
    detail::writeNumber(cfg, s, "max_steering_deg", mrpt::RAD2DEG(max_steering));
    detail::writeNumber(cfg, s, "std_speed_mps", std_speed_mps);
    detail::writeNumber(cfg, s, "std_steering_deg", mrpt::RAD2DEG(std_steering));
}

Vehicle::Vehicle(const Options& options, const Eigen::Vector3d& start_pose)
    : options_(options), ute_(options.ute()), pose_(start_pose)
{
}

void Vehicle::step(const Eigen::Vector2d& u, double dt)
{
    pose_ = hymm::core::uteStep(pose_, u, dt, ute_);
}

Eigen::Vector2d Vehicle::readControls(const Eigen::Vector2d& u,
                                      mrpt::random::CRandomGenerator& rng) const
{
    return {u[0] + options_.std_speed_mps * rng.drawGaussian1D_normalized(),
            u[1] + options_.std_steering * rng.drawGaussian1D_normalized()};
}

}  // namespace hymm::sim
