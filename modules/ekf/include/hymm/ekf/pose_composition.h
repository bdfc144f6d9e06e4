/**
 * @file pose_composition.h
 * @brief 2D pose composition x (+) d (MRPT's CPose2D operator+) with its Jacobians,
 *        the motion model used for odometry increments (CActionRobotMovement2D).
 */
#pragma once

#include <Eigen/Core>

namespace hymm::ekf
{
/**
 * Returns x (+) d = (x + cos(phi) dx - sin(phi) dy, y + sin(phi) dx + cos(phi) dy,
 * wrapToPi(phi + dphi)) for pose `x` = (x, y, phi) and increment `d` = (dx, dy, dphi)
 * expressed in the frame of `x`. Optionally returns J_x = d(x (+) d)/dx and
 * J_d = d(x (+) d)/dd (both 3x3).
 */
Eigen::Vector3d composePose(
    const Eigen::Vector3d& x, const Eigen::Vector3d& d, Eigen::Matrix3d* J_x = nullptr,
    Eigen::Matrix3d* J_d = nullptr);

}  // namespace hymm::ekf
