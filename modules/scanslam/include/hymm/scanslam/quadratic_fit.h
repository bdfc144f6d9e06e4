/**
 * @file quadratic_fit.h
 * @brief Gaussian covariance from point evaluations of a likelihood (thesis 5.4,
 *        Eqs. 5.16-5.17): with C'_i = -2 (ln C_i - ln C_M) and offsets d_i from the
 *        maximum, d_i^T P^-1 d_i = C'_i is linear in the six entries of P^-1; more than
 *        six samples are solved in the least-squares sense by SVD.
 */
#pragma once

#include <optional>
#include <vector>

#include "hymm/scanslam/PointSet.h"

namespace hymm::scanslam
{
/** P^-1 from offsets `d` and values `c` (Eq. 5.17 rows [x^2, 2xy, 2xz, y^2, 2yz, z^2]);
 *  nullopt with fewer than six samples, a rank-deficient design or a result that is not
 *  positive definite. */
std::optional<Mat3> fitInverseCovariance(const std::vector<Vec3>& d, const std::vector<double>& c);

/** The 18 sample offsets used around a maximum: +-s_k along each axis and the 12
 *  diagonals +-s_k +-s_l (k < l). */
std::vector<Vec3> quadraticFitStencil(const Vec3& step);

}  // namespace hymm::scanslam
