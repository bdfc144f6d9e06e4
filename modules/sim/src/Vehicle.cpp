#include "hymm/sim/Vehicle.h"

#include <hymm/core/config_utils.h>
#include <mrpt/core/bits_math.h>

#include <cmath>

#include "config_text.h"

namespace hymm::sim
{
hymm::core::UteParams Vehicle::Options::ute() const
{
    hymm::core::UteParams p;
    p.L = wheelbase_m;
    p.H = encoder_offset_m;
    p.a = offset_a_m;
    p.b = offset_b_m;
    return p;
}

hymm::core::OptionTable Vehicle::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("wheelbase_m", wheelbase_m, "m", above(0, 100), "L (Appendix A)");
    t.real("encoder_offset_m", encoder_offset_m, "m", between(-50, 50), "H: lateral offset of the speed encoder");
    t.real("offset_a_m", offset_a_m, "m", between(-100, 100), "a: tracked point forward of the rear axle");
    t.real("offset_b_m", offset_b_m, "m", between(-100, 100), "b: tracked point left of the rear axle");
    t.real("speed_mps", speed_mps, "m/s", between(0, 100), "encoder speed driven (0: parked)");
    t.degrees("max_steering_deg", max_steering, openInterval(0, 90), "steering limit");
    t.real("std_speed_mps", std_speed_mps, "m/s", between(0, 100), "noise of one speed reading, 1 sigma");
    t.degrees("std_steering_deg", std_steering, between(0, 90), "noise of one steering reading, 1 sigma");
    t.degrees("steering_offset_deg", steering_offset, between(-10, 10),
              "the steering sensor reads this much more than the wheels are turned (a calibration error: "
              "the odometry's heading drifts by about this / L per metre)");
    t.real("odometry_turn_loss_deg_per_m", odometry_turn_loss, "deg/m", between(-10, 10),
           "the odometry reports this much less turn per metre than the vehicle made (wheels of unequal "
           "radii: a pure heading drift per metre)", M_PI / 180);
    t.flag("odometry_bias_correction", odometry_bias_correction,
           "odometry subtracts the second-order bias of the noisy readings' increments "
           "(v H std_steering^2 / L^2 in heading rate on a straight line); false: raw increments, "
           "biased");
    return t;
}

void Vehicle::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                          const std::string& s)
{
    table().load(cfg, s);
    // Eq. A.3 needs 1 - tan(alpha) H / L away from zero; leave room for the noise too.
    constexpr double kSteeringNoiseSigmas = 6.0;
    const double worst = max_steering + kSteeringNoiseSigmas * std_steering + std::abs(steering_offset);
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
    auto copy = *this;
    copy.table().save(cfg, s);
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
            // The offset added last: at 0 the reading is the same double as without it.
            u[1] + options_.std_steering * rng.drawGaussian1D_normalized() + options_.steering_offset};
}

}  // namespace hymm::sim
