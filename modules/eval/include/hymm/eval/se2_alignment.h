/**
 * @file se2_alignment.h
 * @brief Closed-form least-squares rigid 2D alignment (Umeyama / Horn without scale).
 *
 * Finds the rotation theta and translation t minimising sum |R(theta) s_i + t - d_i|^2.
 * With centred points s'_i, d'_i: theta = atan2(sum s' x d', sum s' . d') and
 * t = mean(d) - R mean(s). In 2D this is exactly the SVD solution of Umeyama (1991)
 * without scale, and never returns a reflection.
 */
#pragma once

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace hymm::eval
{
/** p -> R(phi) p + (x, y). */
struct Se2Transform
{
    double x = 0;
    double y = 0;
    double phi = 0;  //!< [rad]

    Eigen::Vector2d apply(const Eigen::Vector2d& p) const;
    Eigen::Matrix2d rotation() const;
    /** Heading of a transformed pose (wrapped to (-pi, pi]). */
    double applyHeading(double heading) const;
    Se2Transform inverse() const;
};

/**
 * Best rigid transform taking `source` onto `target` (paired by index). Returns
 * std::nullopt if the sizes differ, fewer than 2 pairs are given, or the source points
 * are all (numerically) coincident so the rotation is undetermined.
 */
std::optional<Se2Transform> alignSE2(
    const std::vector<Eigen::Vector2d>& source, const std::vector<Eigen::Vector2d>& target);

/**
 * Jacobian of alignSE2's rotation with respect to the source points, the targets held
 * fixed: a 1 x 2n row (x_0, y_0, x_1, y_1, ...). With the source's joint covariance P,
 * J P J^T is the variance of the fitted rotation, i.e. how far the rigid orientation of
 * an estimated point map may be off by its own uncertainty. Same std::nullopt cases as
 * alignSE2.
 */
std::optional<Eigen::RowVectorXd> alignSE2RotationJacobian(
    const std::vector<Eigen::Vector2d>& source, const std::vector<Eigen::Vector2d>& target);

}  // namespace hymm::eval
