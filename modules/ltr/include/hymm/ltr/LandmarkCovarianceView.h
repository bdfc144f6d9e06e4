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
};

}  // namespace hymm::ltr
