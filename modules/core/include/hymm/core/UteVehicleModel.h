/**
 * @file UteVehicleModel.h
 * @brief The UTE (Ackermann) vehicle model of thesis Appendix A, Eq. A.1-A.4,
 *        with its Jacobians (Eq. A.5-A.15, re-derived: the printed A.7/A.9/A.11
 *        drop the Delta-T factor on the steering term).
 *
 * The state tracked is the pose of a reference point rigidly attached to the
 * vehicle at (a, b) from the centre of the rear axle (a forward, b left), with the
 * vehicle heading. With a = b = 0 this is the classic bicycle model (Eq. 2.6).
 * Controls are u = (v_e, alpha): the speed measured by the encoder on the back left
 * wheel, offset H from the axle centre, and the steering angle.
 */
#pragma once

#include <Eigen/Core>

namespace hymm::core
{
/** Geometry of the vehicle [m] (defaults: the UTE of thesis Table A.1 / Eq. A.3). */
struct UteParams
{
    double L = 2.83;  //!< wheelbase [m]
    double H = 0.76;  //!< lateral offset of the speed encoder from the axle centre [m]
    double a = 3.78;  //!< forward offset of the tracked point from the rear axle [m]
    double b = 0.50;  //!< leftward offset of the tracked point from the rear axle [m]
};

/** Speed at the rear-axle centre from the encoder speed (Eq. A.3). Throws if the
 *  steering makes the denominator vanish (|tan(alpha)| H / L >= 0.99). */
double uteAxleSpeed(double v_encoder, double steering, const UteParams& p,
                    double* d_dv = nullptr, double* d_dalpha = nullptr);

/**
 * One Euler step of Eq. A.4 over `dt` seconds from pose `x` = (x, y, phi) with control
 * `u` = (v_e, alpha). Optionally returns F = df/dx (Eq. A.15) and B = df/du (Eq. A.5).
 * The returned heading is wrapped to (-pi, pi].
 */
Eigen::Vector3d uteStep(
    const Eigen::Vector3d& x, const Eigen::Vector2d& u, double dt, const UteParams& p,
    Eigen::Matrix3d* F = nullptr, Eigen::Matrix<double, 3, 2>* B = nullptr);

/**
 * The same Euler step expressed as a pose increment in the frame of the tracked point
 * at the start of the step: (dx, dy, dphi) = dt (v_c - w b, w a, w), w = v_c tan(alpha)/L.
 * It does not depend on the global pose, so it is what odometry reports
 * (CActionRobotMovement2D). Optionally returns d(increment)/du (3x2).
 */
Eigen::Vector3d uteIncrement(
    const Eigen::Vector2d& u, double dt, const UteParams& p,
    Eigen::Matrix<double, 3, 2>* J_u = nullptr);

/**
 * Second-order bias of uteIncrement under zero-mean control noise of covariance `Q`
 * (2x2, over (v_e, alpha)): E[d(u + n)] - d(u) = 1/2 sum_ij Q_ij d2d/du_i du_j. The
 * increment is linear in v_e, so only the alpha-alpha and v_e-alpha terms remain; on a
 * straight line the heading rate is biased by v_e H std_alpha^2 / L^2 (0.0022 rad/s at
 * 3 m/s, 5 deg, the UTE geometry: 40 deg over a 315 s run). Odometry that composes the
 * increments of noisy readings subtracts it to report the conditional mean its covariance
 * describes (the reading noise enters both ways, so the same term is the bias either way).
 */
Eigen::Vector3d uteIncrementNoiseBias(
    const Eigen::Vector2d& u, double dt, const UteParams& p, const Eigen::Matrix2d& Q);

}  // namespace hymm::core
