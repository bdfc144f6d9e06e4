/**
 * @file AffineRegionMap.h
 * @brief Map from a region's reference triangle to its current triangle.
 *
 * Local layers store their content in metric coordinates of the reference triangle
 * (the vertex positions when the region was created). Because local coordinates
 * (alpha, beta) never change after fusion (Sec. 3.6), the position today of a
 * reference point p_ref is the point with the same barycentric coordinates in the
 * current triangle: p = C + A (p_ref - R1), with A = D_cur D_ref^{-1} and R1, C the
 * first reference and current vertices. This is the unique affine map that sends the
 * three reference vertices onto the three current ones. Directions (differences of
 * points) map with A alone. rigidPart() gives the rotation and translation that fit the
 * same vertex pairs best (an AffineRegionMap too, but no longer exact at the vertices).
 */
#pragma once

#include "hymm/ltr/TriangleFrame.h"

namespace hymm::ltr
{
class AffineRegionMap
{
public:
    /** From the reference frame to the current frame (both already validated). */
    AffineRegionMap(const TriangleFrame& reference, const TriangleFrame& current);

    /** Identity map. */
    AffineRegionMap();

    Eigen::Vector2d mapPoint(const Eigen::Vector2d& p_ref) const { return a_ * p_ref + t_; }
    Eigen::Vector2d mapDirection(const Eigen::Vector2d& d_ref) const { return a_ * d_ref; }
    /** Current global point back to reference coordinates. */
    Eigen::Vector2d inverseMapPoint(const Eigen::Vector2d& p) const { return a_inv_ * (p - t_); }
    Eigen::Vector2d inverseMapDirection(const Eigen::Vector2d& d) const { return a_inv_ * d; }

    /** The map from the current frame back to the reference frame. */
    AffineRegionMap inverse() const;

    /** Linear part A (current = A reference + t). */
    const Eigen::Matrix2d& linear() const { return a_; }
    const Eigen::Vector2d& translation() const { return t_; }

    /** The rigid map (rotation and translation) that best fits the pairs (x_k, this map
     *  of x_k) in the least-squares sense (2-D Kabsch), x_k the three `reference`
     *  vertices this map was built from. Inside the triangle it differs from the affine
     *  map by the triangle's deformation; outside it does not extrapolate that
     *  deformation. The identity's is the identity; the inverse's, fitted on the current
     *  vertices, is the inverse of this one. Computed on demand: region content never
     *  needs it. */
    AffineRegionMap rigidPart(const TriangleFrame::Vertices& reference) const;

private:
    AffineRegionMap(const Eigen::Matrix2d& a, const Eigen::Vector2d& t);

    Eigen::Matrix2d a_;
    Eigen::Matrix2d a_inv_;
    Eigen::Vector2d t_;
};

}  // namespace hymm::ltr
