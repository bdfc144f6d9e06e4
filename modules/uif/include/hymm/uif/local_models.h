/**
 * @file local_models.h
 * @brief Local vehicle pose and local coordinates of a delayed return (thesis Sec. 3.7.3,
 *        Eq. 3.27-3.30), with analytic Jacobians.
 *
 * Notation: vehicle pose x_v = (x, y, phi) in the global frame, sensor mounting pose
 * s = (sx, sy, sphi) on the vehicle, raw return z = (range, bearing), triangle L1, L2, L3
 * with axes D = [L2 - L1, L3 - L1] (ltr::TriangleFrame). The global return is
 * g(x_v, z) = hymm::core::inverseRangeBearing (Eq. 2.53's g) and its local coordinates
 * l = D^{-1} (g - L1) (Eq. 3.9).
 *
 * Corrections to the transcribed text (each checked numerically in local_models_test):
 *  - Eq. 3.28 gamma = phi_v - atan((L2y - L1y) / (L2x - L1x)) loses the quadrant of the
 *    axis a = L2 - L1; the heading of that axis is atan2(a_y, a_x), used here, and gamma is
 *    wrapped to (-pi, pi].
 *  - Eq. 3.29 x_d = h(x_v^L, z) is not a function of the local pose and z alone: since the
 *    frame is affine (not a rigid frame), l = [alpha, beta]^T + D^{-1} Rot(gamma + theta_a)
 *    q(z), with q the return in the vehicle frame, also depends on the triangle's shape
 *    through D^{-1} Rot(theta_a). Eq. 3.30 therefore misses the explicit vertex term
 *    dh/dL P_LL dh/dL^T and its cross terms with the local pose; it also drops the
 *    transpose of the last factor (grad_z h R grad_z h^T).
 * The store evaluates the exact first-order covariance instead (DelayedDenseStore.h).
 */
#pragma once

#include <hymm/ltr/TriangleFrame.h>

#include <Eigen/Core>

namespace hymm::uif
{
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Mat23 = Eigen::Matrix<double, 2, 3>;
using Mat26 = Eigen::Matrix<double, 2, 6>;
using Mat36 = Eigen::Matrix<double, 3, 6>;

/**
 * Local vehicle pose x_v^L = (alpha, beta, gamma) in `frame` (Eq. 3.27-3.28): (alpha,
 * beta) are the local coordinates of the vehicle position, gamma its heading relative to
 * the axis L2 - L1. Jacobians: J_pose = d x_v^L / d x_v (3x3), J_vertices = d x_v^L /
 * d(L1, L2, L3) (3x6).
 */
Vec3 localVehiclePose(
    const Vec3& pose, const hymm::ltr::TriangleFrame& frame, Mat3* J_pose = nullptr,
    Mat36* J_vertices = nullptr);

/** The global pose of a local vehicle pose (inverse of localVehiclePose). */
Vec3 globalVehiclePose(const Vec3& local_pose, const hymm::ltr::TriangleFrame& frame);

/** Jacobians of the local coordinates of a return seen from a global vehicle pose. */
struct PointLocalJacobians
{
    Mat23 pose = Mat23::Zero();      //!< d l / d x_v
    Mat2 z = Mat2::Zero();           //!< d l / d z
    Mat26 vertices = Mat26::Zero();  //!< d l / d (L1, L2, L3)
};

/** Local coordinates l of the return `z` seen by the sensor `sensor` of a vehicle at the
 *  global pose `pose` (the composition of Eq. 2.53's g with Eq. 3.9). */
Vec2 pointLocal(
    const Vec3& pose, const Vec3& sensor, const Vec2& z, const hymm::ltr::TriangleFrame& frame,
    PointLocalJacobians* J = nullptr);

/** Jacobians of Eq. 3.29 written exactly (see the file comment). */
struct PointFromLocalPoseJacobians
{
    Mat23 local_pose = Mat23::Zero();  //!< grad_{x_v^L} h
    Mat2 z = Mat2::Zero();             //!< grad_z h
    Mat26 vertices = Mat26::Zero();    //!< explicit d h / d (L1, L2, L3) at fixed x_v^L
};

/** Eq. 3.29: local coordinates of the return from the LOCAL vehicle pose and z. */
Vec2 pointLocalFromLocalPose(
    const Vec3& local_pose, const Vec3& sensor, const Vec2& z, const hymm::ltr::TriangleFrame& frame,
    PointFromLocalPoseJacobians* J = nullptr);

}  // namespace hymm::uif
