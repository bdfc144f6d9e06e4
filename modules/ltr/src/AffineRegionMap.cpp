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
}

AffineRegionMap::AffineRegionMap()
    : a_(Eigen::Matrix2d::Identity()), a_inv_(Eigen::Matrix2d::Identity()), t_(Eigen::Vector2d::Zero())
{
}

AffineRegionMap::AffineRegionMap(const Eigen::Matrix2d& a, const Eigen::Vector2d& t)
    : a_(a), a_inv_(a.inverse()), t_(t)
{
}

AffineRegionMap AffineRegionMap::rigidPart(const TriangleFrame::Vertices& reference) const
{
    // 2-D Kabsch: the rotation maximising sum (y_k - cy) . R (x_k - cx) has angle
    // atan2(sum x' x y', sum x' . y') (cross and dot products of the centred vertices),
    // i.e. (cos, sin) = (dot, cross) / |(dot, cross)|.
    const Eigen::Vector2d cx = (reference[0] + reference[1] + reference[2]) / 3.0;
    const Eigen::Vector2d cy = mapPoint(cx);  // an affine map keeps the centroid
    double cross = 0, dot = 0;
    for (const Eigen::Vector2d& v : reference)
    {
        const Eigen::Vector2d x = v - cx, y = mapDirection(x);
        cross += x.x() * y.y() - x.y() * y.x();
        dot += x.dot(y);
    }
    const double n = std::hypot(dot, cross);  // > 0 for any non-degenerate pair of frames
    Eigen::Matrix2d r = Eigen::Matrix2d::Identity();
    if (n > 0) r << dot / n, -cross / n, cross / n, dot / n;
    return AffineRegionMap(r, cy - r * cx);
}

AffineRegionMap AffineRegionMap::inverse() const { return AffineRegionMap(a_inv_, -a_inv_ * t_); }

}  // namespace hymm::ltr
