#include "hymm/sim/Simulator.h"

#include <mrpt/poses/CPose2D.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace hymm::sim
{
namespace
{
// Noise streams, each with its own generator (see the class comment).
enum Stream : uint64_t
{
    kControls = 1,
    kLaser = 2,
    kDetector = 3,
    kIntensity = 4
};

// A run that has not finished its laps after this many times the nominal time is
// declared stuck (the vehicle cannot follow the loop).
constexpr double kLapTimeFactor = 3.0;

/** splitmix64 of (seed, stream): well-separated 32-bit seeds for the generators. */
uint32_t streamSeed(long seed, Stream stream)
{
    uint64_t z = static_cast<uint64_t>(seed) * 0x9E3779B97F4A7C15ULL + stream;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return static_cast<uint32_t>(z ^ (z >> 31));
}

double stepLimit(const Scenario& s, const PathFollower& f)
{
    const double dt = s.run.dt_s;
    if (s.run.duration_s > 0) return std::ceil(s.run.duration_s / dt) + 1;
    const double nominal = s.run.laps * f.path()->length() / s.vehicle.speed_mps;
    return kLapTimeFactor * nominal / dt + 100;
}
}  // namespace

Simulator::Simulator(const Scenario& scenario)
    : scenario_(scenario),
      follower_(scenario.path, scenario.vehicle.ute(), scenario.vehicle.max_steering),
      world_(World::build(scenario.world, follower_.path() ? &*follower_.path() : nullptr)),
      vehicle_(scenario.vehicle, follower_.startPose()),
      odometry_(scenario.vehicle.ute(), scenario.vehicle.std_speed_mps,
                scenario.vehicle.std_steering, scenario.vehicle.odometry_bias_correction,
                scenario.vehicle.odometry_turn_loss),
      control_rng_(streamSeed(scenario.run.seed, kControls)),
      laser_every_(scenario.stepsPerPeriod(scenario.laser.period_s)),
      detector_every_(scenario.stepsPerPeriod(scenario.detector.period_s)),
      start_(mrpt::Clock::fromDouble(scenario.run.start_time_s)),
      step_limit_(stepLimit(scenario, follower_)),
      dr_pose_(vehicle_.pose())
{
    if (scenario.laser.enabled)
        laser_.emplace(scenario.laser, streamSeed(scenario.run.seed, kLaser),
                       streamSeed(scenario.run.seed, kIntensity));
    if (scenario.detector.enabled)
        detector_.emplace(scenario.detector, streamSeed(scenario.run.seed, kDetector));
}

mrpt::Clock::time_point Simulator::stampAt(long k) const
{
    // Integer ticks (100 ns) from the start: no drift from summing dt.
    return start_ + mrpt::Clock::duration(std::llround(k * scenario_.run.dt_s * 1e7));
}

bool Simulator::next(SimFrame& frame)
{
    while (!done_)
    {
        const bool laser_due = laser_ && k_ % laser_every_ == 0;
        const bool detector_due = detector_ && k_ % detector_every_ == 0;
        if (laser_due || detector_due) fillFrame(frame, laser_due, detector_due);
        advance();
        if (laser_due || detector_due) return true;
    }
    return false;
}

void Simulator::fillFrame(SimFrame& f, bool laser_due, bool detector_due)
{
    f.index = frames_++;
    f.t = k_ * scenario_.run.dt_s;
    f.stamp = stampAt(k_);
    f.true_pose = vehicle_.pose();
    f.dr_pose = dr_pose_;
    f.odometry_mean = odometry_.mean();
    f.odometry_cov = odometry_.covariance();
    odometry_.reset();
    f.true_controls = std::move(true_controls_);
    f.measured_controls = std::move(measured_controls_);
    true_controls_.clear();
    measured_controls_.clear();
    f.scan = laser_due ? laser_->observe(world_, f.true_pose, f.t, f.stamp) : nullptr;
    f.detections = detector_due ? detector_->observe(world_, f.true_pose, f.t, f.stamp) : nullptr;
}

void Simulator::advance()
{
    const double dt = scenario_.run.dt_s;
    const Eigen::Vector2d u(scenario_.vehicle.speed_mps, follower_.steering(vehicle_.pose()));
    const Eigen::Vector2d measured = vehicle_.readControls(u, control_rng_);
    vehicle_.step(u, dt);
    // Dead reckoning composes the same increments the odometry reports.
    const Eigen::Vector3d d = odometry_.addStep(measured, dt);
    const mrpt::poses::CPose2D dr =
        mrpt::poses::CPose2D(dr_pose_[0], dr_pose_[1], dr_pose_[2]) + mrpt::poses::CPose2D(d[0], d[1], d[2]);
    dr_pose_ = Eigen::Vector3d(dr.x(), dr.y(), dr.phi());
    true_controls_.push_back(u);
    measured_controls_.push_back(measured);
    ++k_;

    if (scenario_.run.duration_s > 0)
        done_ = k_ * dt > scenario_.run.duration_s + 1e-9;
    else
        done_ = follower_.progress() >= scenario_.run.laps * follower_.path()->length();
    if (!done_ && k_ > step_limit_)
        throw std::runtime_error(
            "simulation '" + scenario_.run.name + "': the vehicle did not complete " +
            std::to_string(scenario_.run.laps) + " lap(s) of the " +
            std::to_string(follower_.path()->length()) + " m loop in " + std::to_string(k_ * dt) +
            " s; the loop may be too tight for [Vehicle] max_steering_deg or "
            "[PathFollower] lookahead_m");
}

}  // namespace hymm::sim
