/**
 * @file OdometryAccumulator.h
 * @brief Composes the pose increments of the measured controls between two sensory
 *        frames, with the covariance propagated from the control noise: what the
 *        simulator writes as the frame's CActionRobotMovement2D.
 *
 * Each dead-reckoning step adds d = hymm::core::uteIncrement(u, dt) (Eq. A.4 in the frame
 * of the tracked point), so composing the increments from a pose reproduces integrating
 * uteStep with the same controls. With D the increment so far and Q = diag(std_speed^2,
 * std_steering^2) the noise of one control reading,
 *     D' = D (+) d,   P' = J_D P J_D^T + J_d (J_u Q J_u^T) J_d^T,
 * J_D, J_d the Jacobians of the pose composition and J_u = d(d)/du. With
 * `correct_bias`, d is the conditional mean of the increment given the reading,
 * uteIncrement(u) - uteIncrementNoiseBias(u, Q): the raw increment of a noisy reading is
 * biased at second order (the heading rate by v H std_steering^2 / L^2 on a straight
 * line), a drift P does not describe. covariance() adds a
 * tiny floor (kFloorStdXy, kFloorStdPhi) so that the matrix is positive definite even
 * for zero steps or a parked vehicle.
 */
#pragma once

#include <hymm/core/UteVehicleModel.h>

#include <Eigen/Core>

namespace hymm::sim
{
class OdometryAccumulator
{
public:
    static constexpr double kFloorStdXy = 1e-4;   //!< [m], far below any control noise
    static constexpr double kFloorStdPhi = 1e-5;  //!< [rad]

    /** `turn_loss` [rad/m]: every increment reports this much less turn per metre than
     *  the readings give (wheels of unequal radii), its translation turned by half of it. */
    OdometryAccumulator(const hymm::core::UteParams& ute, double std_speed, double std_steering,
                        bool correct_bias = true, double turn_loss = 0);

    /** Starts a new increment at the identity. */
    void reset();

    /** Adds one step of `dt` seconds with the measured control `u` = (v_e, alpha) and
     *  returns the increment it composed (bias-corrected or raw, as constructed). */
    Eigen::Vector3d addStep(const Eigen::Vector2d& u, double dt);

    /** (dx, dy, dphi): the pose at the last step in the frame of the pose at reset(). */
    const Eigen::Vector3d& mean() const { return mean_; }

    /** Covariance of mean(), including the floor. */
    Eigen::Matrix3d covariance() const;

    size_t steps() const { return steps_; }

private:
    Eigen::Vector3d increment(const Eigen::Vector2d& u, double dt, Eigen::Matrix<double, 3, 2>* J_u) const;

    const hymm::core::UteParams ute_;
    Eigen::Matrix2d Q_;
    bool correct_bias_ = true;
    double turn_loss_ = 0;  //!< [rad/m]
    Eigen::Vector3d mean_;
    Eigen::Matrix3d cov_;
    size_t steps_ = 0;
};

}  // namespace hymm::sim
