/**
 * @file pose_landmark_model.h
 * @brief Observation model of a 3-DOF pose landmark (Scan-SLAM, thesis 5.3.2, Eq. 5.15):
 *        the pose of the landmark frame x_L as seen from the sensor, whose global pose is
 *        the vehicle pose composed with the sensor's mounting s: z = (x_v (+) s)^-1 (+) x_L.
 *        With s = 0 this is Eq. 5.15. Also its inverse, used to add a landmark.
 */
#pragma once

#include <Eigen/Core>

namespace hymm::ekf
{
/** z = h(x_v, x_L) for a sensor mounted at `sensor` = (x, y, yaw) on the vehicle; the
 *  angle is wrapped to (-pi, pi]. Optional Jacobians H_v = dh/dx_v, H_l = dh/dx_L. */
Eigen::Vector3d poseLandmarkObservation(const Eigen::Vector3d& x_v, const Eigen::Vector3d& x_l,
                                        const Eigen::Vector3d& sensor,
                                        Eigen::Matrix3d* H_v = nullptr,
                                        Eigen::Matrix3d* H_l = nullptr);

/** x_L = (x_v (+) s) (+) z, the inverse of poseLandmarkObservation in x_L, with
 *  G_v = dx_L/dx_v and G_z = dx_L/dz (augmentation, thesis Eq. 2.53 for a 3-DOF block). */
Eigen::Vector3d poseLandmarkFromObservation(const Eigen::Vector3d& x_v, const Eigen::Vector3d& z,
                                            const Eigen::Vector3d& sensor,
                                            Eigen::Matrix3d* G_v = nullptr,
                                            Eigen::Matrix3d* G_z = nullptr);

}  // namespace hymm::ekf
