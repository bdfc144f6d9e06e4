#include "hymm/denseslam/VirtualLandmarkView.h"

#include <stdexcept>
#include <string>

namespace hymm::denseslam
{
bool VirtualLandmarkView::has(long id) const
{
    return isVirtual(id) ? ekf_.passive().has(id) : real_.has(id);
}

Eigen::Vector2d VirtualLandmarkView::mean(long id) const
{
    return isVirtual(id) ? Eigen::Vector2d(ekf_.passive().mean(id)) : real_.mean(id);
}

Eigen::Matrix2d VirtualLandmarkView::cov(long id) const
{
    return isVirtual(id) ? Eigen::Matrix2d(ekf_.passive().cov(id)) : real_.cov(id);
}

Eigen::Matrix2d VirtualLandmarkView::crossCov(long id_a, long id_b) const
{
    const bool va = isVirtual(id_a), vb = isVirtual(id_b);
    if (!va && !vb) return real_.crossCov(id_a, id_b);
    if (va && vb)
    {
        // Not stored (passive-passive terms are dropped): reported as zero, so a
        // triangle with two virtual vertices never passes the correlation condition.
        return id_a == id_b ? cov(id_a) : Eigen::Matrix2d::Zero();
    }
    const long v = va ? id_a : id_b, l = va ? id_b : id_a;
    if (!real_.has(l))
        throw std::out_of_range("VirtualLandmarkView: unknown landmark id " + std::to_string(l));
    // Passive cross terms are stored against the whole active state (Ex. 3.3).
    const Eigen::Matrix2d pvl = ekf_.passive().crossCov(v, ekf_.landmarkBlock(l).offset, 2);
    return va ? pvl : Eigen::Matrix2d(pvl.transpose());
}

Eigen::Matrix<double, 2, 3> VirtualLandmarkView::crossVehicle(long id) const
{
    if (!isVirtual(id)) return real_.crossVehicle(id);
    return ekf_.passive().crossCov(id, 0, 3);
}

std::vector<long> VirtualLandmarkView::ids() const
{
    std::vector<long> out = real_.ids();
    for (const long v : virtual_)
        if (ekf_.passive().has(v)) out.push_back(v);
    return out;
}

std::vector<long> VirtualLandmarkView::idsNear(const Eigen::Vector2d& centre, double radius) const
{
    std::vector<long> out = real_.idsNear(centre, radius);
    for (const long v : virtual_)
        if (ekf_.passive().has(v) && (mean(v) - centre).norm() <= radius) out.push_back(v);
    return out;
}

}  // namespace hymm::denseslam
