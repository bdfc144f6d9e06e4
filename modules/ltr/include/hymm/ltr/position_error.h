/**
 * @file position_error.h
 * @brief Error of a dense-map point's global position (thesis Sec. 3.6).
 *
 * A point stored in an LTR keeps its local coordinates l = (alpha, beta) forever;
 * its global position x = L1 + D l moves only through the three vertex estimates.
 * First-order propagation with the Jacobians of TriangleFrame gives
 *   P_x = J_L P_LLL J_L^T + D P_l D^T,
 * where J_L = [w1 I, w2 I, w3 I] (barycentric weights), P_LLL is the joint 6x6
 * covariance of the three vertices (cross-covariances included: they are what makes
 * a well-chosen region rigid, Sec. 3.5) and P_l the covariance of the local
 * coordinates themselves (zero for a point that is never re-estimated).
 * An EKF correction (Delta L1, Delta L2, Delta L3) of the vertices (Eq. 3.12, 3.16)
 * moves the point by w1 Delta L1 + w2 Delta L2 + w3 Delta L3, exactly (the map is
 * linear in the vertices for fixed l).
 */
#pragma once

#include "hymm/ltr/LandmarkCovarianceView.h"
#include "hymm/ltr/TriangleFrame.h"

#include <array>

namespace hymm::ltr
{
/** Joint 6x6 covariance of the three landmarks `ids` (blocks ordered as `ids`). */
Eigen::Matrix<double, 6, 6> jointVertexCovariance(
    const LandmarkCovarianceView& view, const std::array<long, 3>& ids);

/** Global covariance of a point with local coordinates `local` in the triangle whose
 *  axes are `frame` (mean vertices), given the joint vertex covariance and,
 *  optionally, the covariance of the local coordinates. */
Eigen::Matrix2d globalPositionCovariance(
    const TriangleFrame& frame, const Eigen::Vector2d& local,
    const Eigen::Matrix<double, 6, 6>& vertex_cov,
    const Eigen::Matrix2d& local_cov = Eigen::Matrix2d::Zero());

/** Same, reading the vertex means and joint covariance from `view`. Throws
 *  std::invalid_argument if the current triangle is degenerate. */
Eigen::Matrix2d globalPositionCovariance(
    const LandmarkCovarianceView& view, const std::array<long, 3>& ids,
    const Eigen::Vector2d& local, const Eigen::Matrix2d& local_cov = Eigen::Matrix2d::Zero());

/** Displacement of a stored point when its vertices are corrected by `delta`
 *  (Delta L1, Delta L2, Delta L3): sum_k w_k Delta L_k. */
Eigen::Vector2d globalDisplacement(
    const Eigen::Vector2d& local, const std::array<Eigen::Vector2d, 3>& delta);

/** Covariance of the local coordinates of a point observed at global position x with
 *  covariance P_xx, its cross-covariance P_xL with the vertices (2x6) and the joint
 *  vertex covariance: the App. C Jacobians applied to the joint Gaussian of
 *  (x, L1, L2, L3). Small when x and the vertices are highly correlated (Sec. 3.3). */
Eigen::Matrix2d localCoordinatesCovariance(
    const TriangleFrame& frame, const Eigen::Vector2d& x, const Eigen::Matrix2d& p_xx,
    const Eigen::Matrix<double, 2, 6>& p_xl, const Eigen::Matrix<double, 6, 6>& vertex_cov);

/** Error that a return at global position `x`, seen now from the vehicle, would carry
 *  for ever in its local coordinates if it were fused into the triangle `ids` now (Sec.
 *  3.6, 3.7.3: the local vehicle uncertainty). The return is x = g(x_v, z) with z held
 *  fixed, so P_xx = G P_vv G^T and P_xL = G P_vL with G = dx/dx_v = [I, (-(x_y - v_y),
 *  x_x - v_x)^T]; then localCoordinatesCovariance, mapped back to metres with the
 *  current axes (D P_l D^T). The sensor noise of the return is left out: it does not
 *  depend on the region. Throws std::invalid_argument if the current triangle is
 *  degenerate. */
Eigen::Matrix2d localFusionCovariance(
    const LandmarkCovarianceView& view, const std::array<long, 3>& ids, const Eigen::Vector2d& x);

}  // namespace hymm::ltr
