/**
 * @file EkfCovarianceView.h
 * @brief hymm::ltr::LandmarkCovarianceView over a live EkfSlam (thesis Sec. 3.2, UIF).
 *
 * The LTR code reads the feature map through this view: it holds a reference to the
 * filter and reads blocks of its mean and covariance in place (no copy of P). Only
 * 2-DOF point landmarks are visible, and by default only confirmed ones: a tentative
 * landmark may still be pruned at the end of a later step, and a region anchored on it
 * would have to be dropped with its dense content.
 *
 * The view must not outlive the filter, and it reflects the filter's state at the time
 * of each call (no snapshot). With `pose_landmarks`, 3-DOF pose landmarks (scan
 * landmarks, high-level landmarks: x, y, phi) are visible too, as the point at their
 * frame's origin (the first two rows of their block): regions on scan landmarks, thesis
 * 6.2. Cost: has/mean/cov/crossCov/crossVehicle are O(1) (hash
 * lookup of the block); ids() is O(number of landmarks); idsNear() is one pass over the
 * layout's blocks reading the mean vector in place (no hashing, about 1 ns per landmark:
 * a few microseconds at 2000 landmarks, see docs/benchmarks.md).
 */
#pragma once

#include <hymm/ekf/EkfSlam.h>
#include <hymm/ltr/LandmarkCovarianceView.h>

namespace hymm::denseslam
{
class EkfCovarianceView : public hymm::ltr::LandmarkCovarianceView
{
public:
    /** `confirmed_only`: hide tentative landmarks (the default); `pose_landmarks`: show
     *  3-DOF pose landmarks as their frame's origin. */
    explicit EkfCovarianceView(const ekf::EkfSlam& ekf, bool confirmed_only = true, bool pose_landmarks = false)
        : ekf_(ekf), confirmed_only_(confirmed_only), pose_landmarks_(pose_landmarks)
    {
    }

    bool has(long id) const override;
    /** The calls below throw std::out_of_range for an id that has() rejects. */
    Eigen::Vector2d mean(long id) const override;
    Eigen::Matrix2d cov(long id) const override;
    Eigen::Matrix2d crossCov(long id_a, long id_b) const override;
    Eigen::Matrix<double, 2, 3> crossVehicle(long id) const override;
    Eigen::Matrix3d vehicleCov() const override;
    Eigen::Vector3d vehiclePose() const override;
    /** Visible landmark ids, in state order. */
    std::vector<long> ids() const override;
    /** Visible landmarks within `radius` of `centre`, in state order. */
    std::vector<long> idsNear(const Eigen::Vector2d& centre, double radius) const override;

private:
    /** State offset of a visible landmark; throws std::out_of_range otherwise. */
    Eigen::Index offsetOf(long id) const;
    bool visible(const ekf::LandmarkBlock& b) const
    {
        return !b.auxiliary && (b.dim == 2 || (pose_landmarks_ && b.dim == 3)) &&
               (!confirmed_only_ || b.confirmed);
    }

    const ekf::EkfSlam& ekf_;
    const bool confirmed_only_;
    const bool pose_landmarks_;
};

}  // namespace hymm::denseslam
