/**
 * @file PathFollower.h
 * @brief Steers the simulated vehicle around a closed loop of waypoints: pure pursuit
 *        of the vehicle's tracked point, computed on the true state.
 *
 * Pure pursuit picks the goal G on the loop `lookahead_m` ahead of the tracked point P
 * and the steering whose circle takes P through G. With constant steering the vehicle
 * turns about the instantaneous centre C = (0, R) in the rear-axle frame (R = L / tan
 * alpha), so |C - P| = |C - G| with P = (a, b) gives
 *     tan(alpha) = 2 L (g_y - b) / (g_x^2 + g_y^2 - a^2 - b^2),
 * G = (g_x, g_y) in the rear-axle frame; with a = b = 0 this is the classic
 * 2 L sin(eta) / l_d. The result is clamped to the vehicle's steering limit.
 *
 * A single waypoint means a parked vehicle there, facing +x (the loop is not used).
 */
#pragma once

#include <hymm/core/UteVehicleModel.h>
#include <hymm/core/OptionTable.h>
#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Core>
#include <optional>

#include "hymm/sim/ClosedPath.h"

namespace hymm::sim
{
class PathFollower
{
public:
    /** Section [PathFollower]. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        std::vector<Vec2> waypoints;  //!< `waypoints = x y x y ...` [m], the loop's corners
        double corner_radius_m = 0;   //!< corners rounded with arcs of this radius [m]
        double lookahead_m = 6;       //!< pure-pursuit look-ahead distance [m]

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();

        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                              const std::string& section) const override;
    };

    PathFollower(const Options& options, const hymm::core::UteParams& ute, double max_steering);

    /** The loop, or nullopt for a parked vehicle. */
    const std::optional<ClosedPath>& path() const { return path_; }

    /** Where the tracked point starts: arc length 0, heading along the loop. */
    Eigen::Vector3d startPose() const;

    /** Steering angle [rad] for the tracked point at `pose`; advances progress(). */
    double steering(const Eigen::Vector3d& pose);

    /** Arc length driven along the loop, counting laps (unwrapped) [m]. */
    double progress() const { return progress_; }

private:
    const Options options_;
    const hymm::core::UteParams ute_;
    const double max_steering_;
    std::optional<ClosedPath> path_;
    double progress_ = 0;
};

}  // namespace hymm::sim
