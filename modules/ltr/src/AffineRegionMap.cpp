/**
 * @file AffineRegionMap.cpp
 */
#include "hymm/ltr/AffineRegionMap.h"

#include <Eigen/LU>

namespace hymm::ltr
{
AffineRegionMap::AffineRegionMap(const TriangleFrame& reference, const TriangleFrame& current)
{
    // Both frames passed their degeneracy limits, so D_ref and A are invertible.
    a_ = current.axes() * reference.axesInverse();
    t_ = current.vertex(0) - a_ * reference.vertex(0);
    a_inv_ = reference.axes() * current.axesInverse();
}

AffineRegionMap::AffineRegionMap()
    : a_(Eigen::Matrix2d::Identity()), a_inv_(Eigen::Matrix2d::Identity()), t_(Eigen::Vector2d::Zero())
{
}

AffineRegionMap::AffineRegionMap(const Eigen::Matrix2d& a, const Eigen::Vector2d& t)
    : a_(a), a_inv_(a.inverse()), t_(t)
{
}

AffineRegionMap AffineRegionMap::inverse() const { return AffineRegionMap(a_inv_, -a_inv_ * t_); }

}  // namespace hymm::ltr
