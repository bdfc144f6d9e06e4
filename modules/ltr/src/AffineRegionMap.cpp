/**
 * @file AffineRegionMap.cpp
 */
#include "hymm/ltr/AffineRegionMap.h"

#include <Eigen/LU>

#include <cmath>

namespace hymm::ltr
{
AffineRegionMap::AffineRegionMap(const TriangleFrame& reference, const TriangleFrame& current)
{
    // Both frames passed their degeneracy limits, so D_ref and A are invertible.
    a_ = current.axes() * reference.axesInverse();
    t_ = current.vertex(0) - a_ * reference.vertex(0);
    a_inv_ = reference.axes() * current.axesInverse();
    // 2-D Kabsch: the rotation maximising sum (y_i - cy) . R (x_i - cx) has angle
    // atan2(sum x' x y', sum x' . y') (cross and dot products of the centred vertices),
    // i.e. (cos, sin) = (dot, cross) / |(dot, cross)|.
    Eigen::Vector2d cx = Eigen::Vector2d::Zero(), cy = Eigen::Vector2d::Zero();
    for (int k = 0; k < 3; ++k)
    {
        cx += reference.vertex(k) / 3.0;
        cy += current.vertex(k) / 3.0;
    }
    double cross = 0, dot = 0;
    for (int k = 0; k < 3; ++k)
    {
        const Eigen::Vector2d x = reference.vertex(k) - cx, y = current.vertex(k) - cy;
        cross += x.x() * y.y() - x.y() * y.x();
        dot += x.dot(y);
    }
    const double n = std::hypot(dot, cross);  // > 0 for any non-degenerate pair of frames
    const double c = n > 0 ? dot / n : 1.0, s = n > 0 ? cross / n : 0.0;
    rigid_a_ << c, -s, s, c;
    rigid_t_ = cy - rigid_a_ * cx;
}

AffineRegionMap::AffineRegionMap()
    : a_(Eigen::Matrix2d::Identity()),
      a_inv_(Eigen::Matrix2d::Identity()),
      t_(Eigen::Vector2d::Zero()),
      rigid_a_(Eigen::Matrix2d::Identity()),
      rigid_t_(Eigen::Vector2d::Zero())
{
}

AffineRegionMap::AffineRegionMap(
    const Eigen::Matrix2d& a, const Eigen::Vector2d& t, const Eigen::Matrix2d& ra, const Eigen::Vector2d& rt)
    : a_(a), a_inv_(a.inverse()), t_(t), rigid_a_(ra), rigid_t_(rt)
{
}

AffineRegionMap AffineRegionMap::inverse() const
{
    const Eigen::Matrix2d rt = rigid_a_.transpose();
    return AffineRegionMap(a_inv_, -a_inv_ * t_, rt, -rt * rigid_t_);
}

AffineRegionMap AffineRegionMap::rigidPart() const
{
    return AffineRegionMap(rigid_a_, rigid_t_, rigid_a_, rigid_t_);
}

}  // namespace hymm::ltr
