/**
 * @file pose_landmark_model.cpp
 * @brief Pose-landmark observation (thesis Eq. 5.15, with a sensor mounting) and its
 *        inverse, with Jacobians (checked against numeric differentiation in the tests).
 */
#include "hymm/ekf/pose_landmark_model.h"

#include <mrpt/math/wrap2pi.h>

#include <cmath>

#include "hymm/ekf/pose_composition.h"

namespace hymm::ekf
{
Eigen::Vector3d poseLandmarkObservation(const Eigen::Vector3d& x_v, const Eigen::Vector3d& x_l,
                                        const Eigen::Vector3d& sensor, Eigen::Matrix3d* H_v,
                                        Eigen::Matrix3d* H_l)
{
    Eigen::Matrix3d J_s;  // d(x_v (+) s)/dx_v
    const Eigen::Vector3d xs = composePose(x_v, sensor, &J_s, nullptr);
    const double c = std::cos(xs.z()), s = std::sin(xs.z());
    const double dx = x_l.x() - xs.x(), dy = x_l.y() - xs.y();
    // Eq. 5.15 with the sensor pose in place of the vehicle's.
    const Eigen::Vector3d z(dx * c + dy * s, -dx * s + dy * c,
                            mrpt::math::wrapToPi(x_l.z() - xs.z()));
    if (H_v)
    {
        Eigen::Matrix3d dz_dxs;
        dz_dxs << -c, -s, z.y(), s, -c, -z.x(), 0, 0, -1;
        *H_v = dz_dxs * J_s;
    }
    if (H_l)
    {
        *H_l << c, s, 0, -s, c, 0, 0, 0, 1;
    }
    return z;
}

Eigen::Vector3d poseLandmarkFromObservation(const Eigen::Vector3d& x_v, const Eigen::Vector3d& z,
                                            const Eigen::Vector3d& sensor, Eigen::Matrix3d* G_v,
                                            Eigen::Matrix3d* G_z)
{
    Eigen::Matrix3d J_s, J_xs, J_z;
    const Eigen::Vector3d xs = composePose(x_v, sensor, &J_s, nullptr);
    const Eigen::Vector3d x_l = composePose(xs, z, &J_xs, &J_z);
    if (G_v) *G_v = J_xs * J_s;
    if (G_z) *G_z = J_z;
    return x_l;
}

}  // namespace hymm::ekf
