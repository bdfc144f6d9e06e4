// The SE(2) pieces of the right-invariant EKF (LinearisationPoint::Invariant), shared by
// the active state (EkfSlam) and the passive blocks (PassiveStates); private to hymm::ekf.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace hymm::ekf::detail
{
/** V(w) = sin w / w I + (1 - cos w) / w J, the left Jacobian of SE(2)'s exponential:
 *  exp((rho, w)) moves a point p to R(w) p + V(w) rho. */
inline Eigen::Matrix2d se2V(double w)
{
    const double s = std::abs(w) < 1e-6 ? 1 - w * w / 6 : std::sin(w) / w;
    const double c = std::abs(w) < 1e-6 ? w / 2 : 2 * std::pow(std::sin(w / 2), 2) / w;  // (1 - cos w) / w
    return (Eigen::Matrix2d() << s, -c, c, s).finished();
}

/** The position at rows [r, r + 2) of `x`, moved from `before` by dp in the additive update,
 *  moved by V dp instead; b at those rows becomes J (p+ - p-), the column of M = I + b e_phi^T
 *  that carries the covariance to the new estimate's coordinates. */
template <class Vec, class BVec>
void retractPosition(Vec& x, const Eigen::VectorXd& before, const Eigen::Matrix2d& V, Eigen::Index r, BVec& b)
{
    const Eigen::Vector2d step = V * (x.template segment<2>(r) - before.segment<2>(r));
    x.template segment<2>(r) = before.segment<2>(r) + step;
    b.template segment<2>(r) = Eigen::Vector2d(-step.y(), step.x());  // J step
}
}  // namespace hymm::ekf::detail
