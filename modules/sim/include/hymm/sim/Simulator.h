/**
 * @file Simulator.h
 * @brief Runs a Scenario step by step and hands out one SimFrame per sensory frame:
 *        the observations of the sensors due at that instant, the odometry since the
 *        previous frame and the ground truth.
 *
 * Every dt_s (the dead-reckoning rate): the path follower steers on the TRUE pose, the
 * vehicle moves with the true control (hymm::core::uteStep), odometry reads the control
 * with noise and composes its increment (OdometryAccumulator), and the dead-reckoning
 * pose integrates the noisy readings. A frame is emitted at every step where a sensor
 * is due (step index a multiple of its period), before that step's motion; frame 0 is
 * at t = 0 with an identity increment. The run ends after duration_s or when the
 * tracked point has driven `laps` times round the loop.
 *
 * Noise streams are independent: controls, laser ranges, laser intensities and detector
 * each draw from their own mrpt::random::CRandomGenerator seeded from [Scenario] seed,
 * so turning a sensor (or the intensities) on or off leaves the others' noise unchanged.
 * Nothing reads the wall clock: the frame timestamps are start_time_s + k dt_s.
 */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/random/RandomGenerators.h>

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "hymm/sim/LandmarkDetector.h"
#include "hymm/sim/LaserSimulator.h"
#include "hymm/sim/OdometryAccumulator.h"
#include "hymm/sim/PathFollower.h"
#include "hymm/sim/Scenario.h"
#include "hymm/sim/Vehicle.h"
#include "hymm/sim/World.h"

namespace hymm::sim
{
struct SimFrame
{
    size_t index = 0;                            //!< 0, 1, ...
    double t = 0;                                //!< time since the start [s]
    mrpt::Clock::time_point stamp;               //!< rawlog timestamp of every object in the frame
    Eigen::Vector3d true_pose;                   //!< tracked point, global (x, y, phi)
    Eigen::Vector3d dr_pose;                     //!< dead reckoning from the true start pose
    Eigen::Vector3d odometry_mean;               //!< increment since the previous frame
    Eigen::Matrix3d odometry_cov;                //!< its covariance (with the floor)
    std::vector<Eigen::Vector2d> true_controls;  //!< per step since the previous frame
    std::vector<Eigen::Vector2d> measured_controls;       //!< what odometry read, same steps
    mrpt::obs::CObservation2DRangeScan::Ptr scan;         //!< null if the laser was not due
    mrpt::obs::CObservationBearingRange::Ptr detections;  //!< null if the detector was not due
};

class Simulator
{
public:
    explicit Simulator(const Scenario& scenario);
    Simulator(const Simulator&) = delete;
    Simulator& operator=(const Simulator&) = delete;

    /** Advances to the next sensory frame; false when the run is over. Throws
     *  std::runtime_error if the vehicle cannot complete its laps (a loop too tight for
     *  the steering limit). */
    bool next(SimFrame& frame);

    const Scenario& scenario() const { return scenario_; }
    const World& world() const { return world_; }
    const PathFollower& follower() const { return follower_; }

    /** Timestamp of step k. */
    mrpt::Clock::time_point stampAt(long k) const;

private:
    void fillFrame(SimFrame& frame, bool laser_due, bool detector_due);
    void advance();

    const Scenario scenario_;
    PathFollower follower_;
    const World world_;
    Vehicle vehicle_;
    OdometryAccumulator odometry_;
    std::optional<LaserSimulator> laser_;
    std::optional<LandmarkDetector> detector_;
    mrpt::random::CRandomGenerator control_rng_;
    const long laser_every_, detector_every_;
    const mrpt::Clock::time_point start_;
    const double step_limit_;  //!< steps after which an unfinished lap is an error

    long k_ = 0;
    size_t frames_ = 0;
    bool done_ = false;
    Eigen::Vector3d dr_pose_;
    std::vector<Eigen::Vector2d> true_controls_, measured_controls_;
};

}  // namespace hymm::sim
