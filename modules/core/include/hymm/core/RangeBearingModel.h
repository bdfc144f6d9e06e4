/**
 * @file RangeBearingModel.h
 * @brief Range-bearing observation of a 2D point landmark from a sensor mounted on
 *        the vehicle (thesis Eq. 2.8 / A.16) and its inverse (landmark initialisation,
 *        Eq. 2.53's g), each with analytic Jacobians.
 *
 * The sensor sits at `sensor` = (sx, sy, sphi) in the vehicle frame (MRPT's
 * CObservation::sensorPose). The printed Jacobian A.18 has the wrong sign on the bearing
 * row's position terms; these are derived from atan2 and verified numerically in tests.
 */
#pragma once

#include <Eigen/Core>

namespace hymm::core
{
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat23 = Eigen::Matrix<double, 2, 3>;

/** Global pose of the sensor given the vehicle pose and the mounting pose. */
Vec3 sensorGlobalPose(const Vec3& vehicle, const Vec3& sensor, Eigen::Matrix3d* J_vehicle = nullptr);

/**
 * Predicted (range, bearing) of landmark `lm` (Eq. 2.8, sensor offset included). The
 * bearing is wrapped to (-pi, pi]. Jacobians: H_v = dh/d(vehicle) (2x3), H_l = dh/d(lm).
 * Throws if the landmark coincides with the sensor (range below 1e-9 m).
 */
Vec2 observeRangeBearing(
    const Vec3& vehicle, const Vec3& sensor, const Vec2& lm, Mat23* H_v = nullptr,
    Mat2* H_l = nullptr);

/**
 * Landmark position from a (range, bearing) observation: the inverse model g of the
 * augmentation (Eq. 2.53). Jacobians: G_v = dg/d(vehicle) (2x3), G_z = dg/dz (2x2).
 */
Vec2 inverseRangeBearing(
    const Vec3& vehicle, const Vec3& sensor, const Vec2& z, Mat23* G_v = nullptr,
    Mat2* G_z = nullptr);

}  // namespace hymm::core
