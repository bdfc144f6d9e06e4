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

std::array<Eigen::Matrix<double, 6, 6>, 3> poseLandmarkObservationHessians(const Eigen::Vector3d& x_v,
                                                                           const Eigen::Vector3d& x_l,
                                                                           const Eigen::Vector3d& sensor)
{
    constexpr double eps = 1e-5;
    std::array<Eigen::Matrix<double, 6, 6>, 3> H;  // every column is set below
    Eigen::Matrix<double, 6, 1> x;
    x << x_v, x_l;
    const auto jacobian = [&sensor](const Eigen::Matrix<double, 6, 1>& s) {
        Eigen::Matrix3d Hv, Hl;
        poseLandmarkObservation(s.head<3>(), s.tail<3>(), sensor, &Hv, &Hl);
        Eigen::Matrix<double, 3, 6> J;
        J << Hv, Hl;
        return J;
    };
    for (int k = 0; k < 6; ++k)
    {
        Eigen::Matrix<double, 6, 1> a = x, b = x;
        a[k] += eps;
        b[k] -= eps;
        const Eigen::Matrix<double, 3, 6> dJ = (jacobian(a) - jacobian(b)) / (2 * eps);
        for (int i = 0; i < 3; ++i) H[static_cast<size_t>(i)].col(k) = dJ.row(i).transpose();
    }
    for (auto& h : H) h = (0.5 * (h + h.transpose())).eval();
    return H;
}

void poseObservationSecondOrder(const Eigen::Vector3d& x_v, const Eigen::Vector3d& x_l,
                                const Eigen::Vector3d& sensor, const Eigen::Matrix<double, 6, 6>& P,
                                Eigen::Vector3d& bias, Eigen::Matrix3d& S2)
{
    const auto Hs = poseLandmarkObservationHessians(x_v, x_l, sensor);
    std::array<Eigen::Matrix<double, 6, 6>, 3> A;
    for (size_t i = 0; i < 3; ++i)
    {
        A[i] = Hs[i] * P;
        bias[static_cast<Eigen::Index>(i)] = 0.5 * A[i].trace();
    }
    for (Eigen::Index i = 0; i < 3; ++i)
        for (Eigen::Index j = 0; j <= i; ++j)
            S2(i, j) = S2(j, i) = 0.5 * (A[static_cast<size_t>(i)] * A[static_cast<size_t>(j)]).trace();
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
