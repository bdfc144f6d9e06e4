/**
 * @file circle_fit.h
 * @brief Least-squares circle fit to 2D points (tree trunks, poles).
 *
 * The fit is the algebraic (Kasa) least-squares circle: minimise
 * sum (x^2 + y^2 + A x + B y + C)^2, a linear problem, followed by a few Gauss-Newton
 * iterations on the geometric residuals |p_i - c| - r. The algebraic fit alone is biased
 * towards small radii when the points cover a short arc with noise, which is exactly the
 * case of a trunk seen by a laser (at most half the circle is visible); the geometric
 * refinement removes most of that bias. Refinement is skipped if it does not reduce the
 * residual.
 */
#pragma once

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace hymm::extract
{
struct Circle
{
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();  //!< [m]
    double radius = 0;                                 //!< [m]
    double rms = 0;  //!< RMS of the geometric residuals |p_i - centre| - radius [m]
};

/**
 * Fits a circle to `points`. Returns std::nullopt when the problem is ill-conditioned:
 * fewer than 3 points, (nearly) collinear points (the radius tends to infinity), or
 * non-finite input. Collinearity is judged by the reciprocal condition number of the
 * algebraic normal equations, compared against `min_rcond`.
 */
std::optional<Circle> fitCircle(const std::vector<Eigen::Vector2d>& points, double min_rcond = 1e-12);

/** RMS of the geometric residuals of `points` with respect to a given circle. */
double circleRms(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& centre,
                 double radius);

}  // namespace hymm::extract
