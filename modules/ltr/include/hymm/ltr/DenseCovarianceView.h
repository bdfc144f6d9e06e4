/**
 * @file DenseCovarianceView.h
 * @brief LandmarkCovarianceView over a dense mean vector and covariance matrix.
 *
 * State layout: the vehicle pose (x, y, phi) at `vehicle_offset`, and each landmark's
 * (x, y) at the offset given by the id -> offset map. Used by tests and by any
 * pipeline whose filter exposes a plain (mean, covariance) pair.
 */
#pragma once

#include "hymm/ltr/LandmarkCovarianceView.h"

#include <map>

namespace hymm::ltr
{
class DenseCovarianceView : public LandmarkCovarianceView
{
public:
    /** Throws std::invalid_argument if sizes or offsets are inconsistent. */
    DenseCovarianceView(
        Eigen::VectorXd mean, Eigen::MatrixXd cov, std::map<long, int> offsets,
        int vehicle_offset = 0);

    bool has(long id) const override { return offsets_.count(id) != 0; }
    Eigen::Vector2d mean(long id) const override;
    Eigen::Matrix2d cov(long id) const override;
    Eigen::Matrix2d crossCov(long id_a, long id_b) const override;
    Eigen::Matrix<double, 2, 3> crossVehicle(long id) const override;
    Eigen::Matrix3d vehicleCov() const override;
    Eigen::Vector3d vehiclePose() const override;
    std::vector<long> ids() const override;
    /** One pass over the id -> offset map, reading the mean vector in place. */
    std::vector<long> idsNear(const Eigen::Vector2d& centre, double radius) const override;

    const Eigen::VectorXd& stateMean() const { return mean_; }
    const Eigen::MatrixXd& stateCov() const { return cov_; }
    /** Replaces the estimate (same layout), e.g. after a filter update. */
    void setEstimate(Eigen::VectorXd mean, Eigen::MatrixXd cov);

private:
    int offsetOf(long id) const;
    void validate() const;

    Eigen::VectorXd mean_;
    Eigen::MatrixXd cov_;
    std::map<long, int> offsets_;
    int vehicle_offset_;
};

}  // namespace hymm::ltr
