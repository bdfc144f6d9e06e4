/**
 * @file LandmarkCovarianceView.h
 * @brief Read-only view of the feature map's joint Gaussian, as the LTR code needs it.
 *
 * The LTR module only reads the feature-map estimate (information flows from the
 * feature map into the dense layers, never back: Sec. 3.2, UIF). The pipeline adapts
 * its EKF to this interface; DenseCovarianceView is a plain implementation over a
 * mean vector and a full covariance matrix.
 */
#pragma once

#include <Eigen/Core>

#include <vector>

namespace hymm::ltr
{
class LandmarkCovarianceView
{
public:
    virtual ~LandmarkCovarianceView() = default;

    /** True if landmark `id` is in the map. Other calls may throw for unknown ids. */
    virtual bool has(long id) const = 0;
    /** Estimated 2D position of landmark `id`. */
    virtual Eigen::Vector2d mean(long id) const = 0;
    /** Marginal covariance P_ii of landmark `id`. */
    virtual Eigen::Matrix2d cov(long id) const = 0;
    /** Cross-covariance P_ab = E[(x_a - mean_a)(x_b - mean_b)^T]. */
    virtual Eigen::Matrix2d crossCov(long id_a, long id_b) const = 0;
    /** Cross-covariance P_iv of landmark `id` with the vehicle pose (x, y, phi). */
    virtual Eigen::Matrix<double, 2, 3> crossVehicle(long id) const = 0;
    /** Vehicle pose covariance P_vv. */
    virtual Eigen::Matrix3d vehicleCov() const = 0;
    /** Vehicle pose (x, y, phi). */
    virtual Eigen::Vector3d vehiclePose() const = 0;
    /** Ids of all landmarks in the map. */
    virtual std::vector<long> ids() const = 0;
    /** True if `id` is a virtual landmark (Sec. 3.5.1): a point carried by the filter but
     *  never observed. Its cross-covariance with another virtual landmark is not kept,
     *  so a region may have at most one virtual vertex. */
    virtual bool isVirtual(long /*id*/) const { return false; }
    /** Ids of the landmarks whose mean lies within `radius` of `centre`
     *  ((mean - centre).norm() <= radius), in the order of ids(). The default filters
     *  ids() through mean() (a lookup per landmark); implementations override it with a
     *  single pass over their storage. The partition's growth uses it instead of ids()
     *  (RegionPartition::updateNear). */
    virtual std::vector<long> idsNear(const Eigen::Vector2d& centre, double radius) const
    {
        std::vector<long> out;
        for (const long id : ids())
            if ((mean(id) - centre).norm() <= radius) out.push_back(id);
        return out;
    }
};

}  // namespace hymm::ltr
