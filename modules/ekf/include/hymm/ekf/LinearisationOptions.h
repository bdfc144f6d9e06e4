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
 */
enum class LinearisationPoint
{
    Current,
    FirstEstimates
};

/** Which Jacobians the covariance of an iterated pose-landmark update uses (Options). */
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
