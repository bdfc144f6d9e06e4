/**
 * @file LinearisationOptions.h
 * @brief Where EkfSlam evaluates its Jacobians and which terms its pose-landmark updates
 *        add (EkfSlam::Options; modules/ekf/README.md).
 */
#pragma once

namespace hymm::ekf
{
/**
 * Where the filter evaluates its Jacobians.
 *  - Current: the standard EKF, at the latest estimate.
 *  - FirstEstimates: the First-Estimates Jacobian EKF (Huang, Mourikis & Roumeliotis,
 *    "Analysis and improvement of the consistency of extended Kalman filter based SLAM",
 *    ICRA 2008). Measurement Jacobians at the predicted vehicle pose x_{k|k-1} and at each
 *    landmark's first estimate (its value when it was added); the position-heading block
 *    of the motion Jacobian is J (p_{k+1|k} - p_{k|k-1}), J = [0 -1; 1 0], so that the
 *    products of motion Jacobians telescope. The linearised system then keeps the
 *    3-dimensional unobservable subspace (global translation and heading) of the
 *    nonlinear one instead of the 2 of the standard EKF, which gains spurious heading
 *    information at every re-observation. Means and innovations use the latest estimate.
 *  - Invariant: the right-invariant EKF (Barrau & Bonnabel, "An EKF-SLAM algorithm with
 *    consistency properties", 2015), written in the filter's (x, y, phi) coordinates.
 *    Jacobians at the latest estimate; every update is applied on the group (each
 *    position p moves by V(w) dp, w the vehicle's heading correction, V the SE(2)
 *    exponential's left Jacobian) and P is carried to the new estimate's coordinates,
 *    P <- M P M^T with M = I + b e_phi^T, b = J (p+ - p-) at every position. In the
 *    invariant coordinates xi_p = dp - dphi_v J p the unobservable subspace is constant,
 *    so current-estimate Jacobians keep it and no first estimate is needed.
 */
enum class LinearisationPoint
{
    Current,
    FirstEstimates,
    Invariant
};

/** Which Jacobians the covariance of an iterated pose-landmark update uses (Options):
 *  the last iterate's, or the one-step update's (FEJ, or invariant at the prior). */
enum class IteratedCovariance
{
    LastIterate,
    FirstEstimates
};

/** Which second-order terms the pose-landmark update adds (Options). */
enum class SecondOrderTerms
{
    Off,
    Covariance,
    Full
};

}  // namespace hymm::ekf
