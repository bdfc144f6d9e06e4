/**
 * @file VirtualLandmarkView.h
 * @brief The LTR view of the feature map plus the virtual landmarks (thesis Sec. 3.5.1).
 *
 * Virtual landmarks are carried by the filter as passive states (Sec. 3.7.1): they
 * receive every correction through their cross-covariance with the active states but
 * never give information back, so the feature map and the path are bitwise the same
 * with or without them. This view shows them to the partition next to the real
 * landmarks of an EkfCovarianceView: mean and covariance from the passive block, the
 * cross-covariance with a landmark or the vehicle from the block's stored cross terms.
 * Two virtual landmarks have no stored cross-covariance (passive-passive terms are not
 * kept): crossCov between two of them is zero, so such a pair never passes the
 * correlation condition, and the partition rejects a second virtual vertex anyway.
 */
#pragma once

#include <hymm/denseslam/EkfCovarianceView.h>
#include <hymm/ekf/EkfSlam.h>
#include <hymm/ltr/LandmarkCovarianceView.h>

#include <set>

namespace hymm::denseslam
{
class VirtualLandmarkView : public hymm::ltr::LandmarkCovarianceView
{
public:
    /** `virtual_ids`: passive block ids of `ekf` that are virtual landmarks (2-DOF);
     *  `pose_landmarks`: the real landmarks include the 3-DOF ones (EkfCovarianceView). */
    VirtualLandmarkView(const ekf::EkfSlam& ekf, const std::set<long>& virtual_ids, bool pose_landmarks = false)
        : ekf_(ekf), real_(ekf, true, pose_landmarks), virtual_(virtual_ids)
    {
    }

    bool has(long id) const override;
    Eigen::Vector2d mean(long id) const override;
    Eigen::Matrix2d cov(long id) const override;
    Eigen::Matrix2d crossCov(long id_a, long id_b) const override;
    Eigen::Matrix<double, 2, 3> crossVehicle(long id) const override;
    Eigen::Matrix3d vehicleCov() const override { return real_.vehicleCov(); }
    Eigen::Vector3d vehiclePose() const override { return real_.vehiclePose(); }
    /** Real landmark ids in state order, then the virtual ones. */
    std::vector<long> ids() const override;
    /** The EKF view's query, plus the virtual landmarks within `radius`. */
    std::vector<long> idsNear(const Eigen::Vector2d& centre, double radius) const override;
    bool isVirtual(long id) const override { return virtual_.count(id) != 0; }

private:
    const ekf::EkfSlam& ekf_;
    const EkfCovarianceView real_;
    const std::set<long>& virtual_;
};

}  // namespace hymm::denseslam
