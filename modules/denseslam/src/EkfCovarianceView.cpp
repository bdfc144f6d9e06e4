#include "hymm/denseslam/EkfCovarianceView.h"

#include <stdexcept>
#include <string>

namespace hymm::denseslam
{
bool EkfCovarianceView::has(long id) const
{
    return ekf_.layout().has(id) && visible(ekf_.layout().get(id));
}

Eigen::Index EkfCovarianceView::offsetOf(long id) const
{
    if (!ekf_.layout().has(id))
        throw std::out_of_range("EkfCovarianceView: unknown landmark id " + std::to_string(id));
    const auto& b = ekf_.layout().get(id);
    if (!visible(b))
        throw std::out_of_range("EkfCovarianceView: landmark " + std::to_string(id) +
                                " is not visible (dim " + std::to_string(b.dim) +
                                (b.confirmed ? ")" : ", tentative)"));
    return static_cast<Eigen::Index>(b.offset);
}

Eigen::Vector2d EkfCovarianceView::mean(long id) const
{
    return ekf_.mean().segment<2>(offsetOf(id));
}

Eigen::Matrix2d EkfCovarianceView::cov(long id) const
{
    const Eigen::Index o = offsetOf(id);
    return ekf_.cov().block<2, 2>(o, o);
}

Eigen::Matrix2d EkfCovarianceView::crossCov(long id_a, long id_b) const
{
    return ekf_.cov().block<2, 2>(offsetOf(id_a), offsetOf(id_b));
}

Eigen::Matrix<double, 2, 3> EkfCovarianceView::crossVehicle(long id) const
{
    return ekf_.cov().block<2, 3>(offsetOf(id), 0);
}

Eigen::Matrix3d EkfCovarianceView::vehicleCov() const { return ekf_.vehicleCov(); }

Eigen::Vector3d EkfCovarianceView::vehiclePose() const { return ekf_.vehiclePose(); }

std::vector<long> EkfCovarianceView::ids() const
{
    std::vector<long> out;
    const auto& blocks = ekf_.layout().blocks();
    out.reserve(blocks.size());
    for (const auto& b : blocks)
        if (visible(b)) out.push_back(b.id);
    return out;
}

std::vector<long> EkfCovarianceView::idsNear(const Eigen::Vector2d& centre, double radius) const
{
    std::vector<long> out;
    const Eigen::VectorXd& x = ekf_.mean();
    for (const auto& b : ekf_.layout().blocks())
        if (visible(b) &&
            (x.segment<2>(static_cast<Eigen::Index>(b.offset)) - centre).norm() <= radius)
            out.push_back(b.id);
    return out;
}

}  // namespace hymm::denseslam
