/**
 * @file joint_covariance.h
 * @brief (private) Joint covariance of a stored scan's passive pose block and three
 *        vertex landmarks, read from the EKF without copying P.
 */
#pragma once

#include <hymm/ekf/EkfSlam.h>
#include <hymm/ltr/TriangleFrame.h>

#include <Eigen/Core>

#include <array>

namespace hymm::uif::detail
{
using Mat9 = Eigen::Matrix<double, 9, 9>;

/** Mean of the passive pose block `passive_id` with its heading wrapped (the filter adds
 *  corrections to it without wrapping). Throws std::out_of_range if unknown. */
Eigen::Vector3d passivePose(const hymm::ekf::EkfSlam& ekf, long passive_id);

/**
 * Joint covariance of (x_s, L1, L2, L3): the passive block's own covariance, its
 * cross-covariance with the vertices (kept by the UIF, Sec. 3.7.1) and the vertices'
 * block of the active P. Fills the current vertex means. O(n_active) (one passive row
 * block is read). Throws std::invalid_argument if a vertex is missing or not a 2D point.
 */
Mat9 jointCovariance(
    const hymm::ekf::EkfSlam& ekf, long passive_id, const std::array<long, 3>& vertex_ids,
    hymm::ltr::TriangleFrame::Vertices& vertices);

}  // namespace hymm::uif::detail
