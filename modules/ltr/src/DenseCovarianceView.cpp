/**
 * @file DenseCovarianceView.cpp
 */
#include "hymm/ltr/DenseCovarianceView.h"

#include <stdexcept>
#include <string>

namespace hymm::ltr
{
DenseCovarianceView::DenseCovarianceView(
    Eigen::VectorXd mean, Eigen::MatrixXd cov, std::map<long, int> offsets, int vehicle_offset)
    : mean_(std::move(mean)),
      cov_(std::move(cov)),
      offsets_(std::move(offsets)),
      vehicle_offset_(vehicle_offset)
{
    validate();
}

void DenseCovarianceView::validate() const
{
    const long n = mean_.size();
    if (cov_.rows() != n || cov_.cols() != n)
        throw std::invalid_argument(
            "DenseCovarianceView: covariance is " + std::to_string(cov_.rows()) + "x" +
            std::to_string(cov_.cols()) + " but the mean has " + std::to_string(n) + " entries");
    if (vehicle_offset_ < 0 || vehicle_offset_ + 3 > n)
        throw std::invalid_argument(
            "DenseCovarianceView: vehicle offset " + std::to_string(vehicle_offset_) +
            " out of range for a state of size " + std::to_string(n));
    for (const auto& [id, off] : offsets_)
        if (off < 0 || off + 2 > n)
            throw std::invalid_argument(
                "DenseCovarianceView: landmark " + std::to_string(id) + " offset " +
                std::to_string(off) + " out of range for a state of size " + std::to_string(n));
}

void DenseCovarianceView::setEstimate(Eigen::VectorXd mean, Eigen::MatrixXd cov)
{
    mean_ = std::move(mean);
    cov_ = std::move(cov);
    validate();
}

int DenseCovarianceView::offsetOf(long id) const
{
    const auto it = offsets_.find(id);
    if (it == offsets_.end())
        throw std::out_of_range("DenseCovarianceView: unknown landmark id " + std::to_string(id));
    return it->second;
}

Eigen::Vector2d DenseCovarianceView::mean(long id) const { return mean_.segment<2>(offsetOf(id)); }

Eigen::Matrix2d DenseCovarianceView::cov(long id) const
{
    const int o = offsetOf(id);
    return cov_.block<2, 2>(o, o);
}

Eigen::Matrix2d DenseCovarianceView::crossCov(long id_a, long id_b) const
{
    return cov_.block<2, 2>(offsetOf(id_a), offsetOf(id_b));
}

Eigen::Matrix<double, 2, 3> DenseCovarianceView::crossVehicle(long id) const
{
    return cov_.block<2, 3>(offsetOf(id), vehicle_offset_);
}

Eigen::Matrix3d DenseCovarianceView::vehicleCov() const
{
    return cov_.block<3, 3>(vehicle_offset_, vehicle_offset_);
}

Eigen::Vector3d DenseCovarianceView::vehiclePose() const
{
    return mean_.segment<3>(vehicle_offset_);
}

std::vector<long> DenseCovarianceView::ids() const
{
    std::vector<long> out;
    out.reserve(offsets_.size());
    for (const auto& kv : offsets_) out.push_back(kv.first);
    return out;
}

std::vector<long> DenseCovarianceView::idsNear(const Eigen::Vector2d& centre, double radius) const
{
    std::vector<long> out;
    for (const auto& [id, off] : offsets_)
        if ((mean_.segment<2>(off) - centre).norm() <= radius) out.push_back(id);
    return out;
}

}  // namespace hymm::ltr
