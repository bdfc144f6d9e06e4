/**
 * @file pose_landmark_model.h
 * @brief Observation model of a 3-DOF pose landmark (Scan-SLAM, thesis 5.3.2, Eq. 5.15):
 *        the pose of the landmark frame x_L as seen from the sensor, whose global pose is
 *        the vehicle pose composed with the sensor's mounting s: z = (x_v (+) s)^-1 (+) x_L.
 *        With s = 0 this is Eq. 5.15. Also its inverse, used to add a landmark.
 */
#pragma once

#include <Eigen/Core>

#include <array>

namespace hymm::ekf
{
/** z = h(x_v, x_L) for a sensor mounted at `sensor` = (x, y, yaw) on the vehicle; the
 *  angle is wrapped to (-pi, pi]. Optional Jacobians H_v = dh/dx_v, H_l = dh/dx_L. */
Eigen::Vector3d poseLandmarkObservation(const Eigen::Vector3d& x_v, const Eigen::Vector3d& x_l,
                                        const Eigen::Vector3d& sensor,
                                        Eigen::Matrix3d* H_v = nullptr,
                                        Eigen::Matrix3d* H_l = nullptr);

/** Second derivatives of poseLandmarkObservation: H[i] is the 6x6 Hessian of z_i with
 *  respect to (x_v, x_l) (the heading component is linear: H[2] = 0). Central differences
 *  of the analytic Jacobians (step 1e-5), which are smooth; checked against second
 *  differences of z in the tests. */
std::array<Eigen::Matrix<double, 6, 6>, 3> poseLandmarkObservationHessians(const Eigen::Vector3d& x_v,
                                                                           const Eigen::Vector3d& x_l,
                                                                           const Eigen::Vector3d& sensor);

/** The second-order terms of z = h(x_v, x_l) over a Gaussian prior of (x_v, x_l) with
 *  joint covariance P (6x6): E[z] = h + bias and cov(z) = J P J^T + S2 to second order,
 *  with A_i = H_i P: bias_i = tr(A_i) / 2, S2_ij = tr(A_i A_j) / 2 (the second-order EKF,
 *  Bar-Shalom, Li & Kirubarajan 2001, Sec. 10.3.3; H_i from
 *  poseLandmarkObservationHessians). */
void poseObservationSecondOrder(const Eigen::Vector3d& x_v, const Eigen::Vector3d& x_l,
                                const Eigen::Vector3d& sensor, const Eigen::Matrix<double, 6, 6>& P,
                                Eigen::Vector3d& bias, Eigen::Matrix3d& S2);

/** x_L = (x_v (+) s) (+) z, the inverse of poseLandmarkObservation in x_L, with
 *  G_v = dx_L/dx_v and G_z = dx_L/dz (augmentation, thesis Eq. 2.53 for a 3-DOF block). */
Eigen::Vector3d poseLandmarkFromObservation(const Eigen::Vector3d& x_v, const Eigen::Vector3d& z,
                                            const Eigen::Vector3d& sensor,
                                            Eigen::Matrix3d* G_v = nullptr,
                                            Eigen::Matrix3d* G_z = nullptr);

}  // namespace hymm::ekf
