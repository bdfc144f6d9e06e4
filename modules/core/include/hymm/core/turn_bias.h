/**
 * @file turn_bias.h
 * @brief Wheels that turn too little per metre (unequal radii): the increment they
 *        report corrected by, or distorted by, a turn bias b [rad/m]. One formula for
 *        the filter's prediction (EkfSlam::predictOdometryWithTurnBias), the pipeline's
 *        matcher start and the simulator's miscalibrated wheels.
 */
#pragma once

#include <Eigen/Core>

namespace hymm::core
{
/**
 * The odometry increment `d` of wheels that turn `b` rad per metre too little: its
 * heading gains b s and its translation turns by b s / 2 (the extra turn accrues along
 * the step, so the chord takes the mid-point heading), s = |(dx, dy)|. With -b: the
 * increment such wheels report for a true `d`. Optionally returns d(result)/db (3x1)
 * and d(result)/dd (3x3).
 */
Eigen::Vector3d turnBiasedIncrement(const Eigen::Vector3d& d, double b, Eigen::Vector3d* J_b = nullptr,
                                    Eigen::Matrix3d* J_d = nullptr);

}  // namespace hymm::core
