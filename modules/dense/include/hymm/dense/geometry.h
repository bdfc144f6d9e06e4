/**
 * @file geometry.h
 * @brief Small 2D geometry used to split laser beams between regions.
 *
 * Free-space rays are straight segments. An affine map (reference -> current frame of
 * a region, DESIGN.md) keeps segments straight and preserves the parameter t along
 * them, so a beam can be clipped to a triangle in either frame: the clipped end
 * points map to each other.
 */
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

namespace hymm::dense
{
/** Parameter interval [t0, t1] (0 <= t0 <= t1 <= 1) of the segment a + t (b - a). */
struct SegmentInterval
{
    double t0 = 0;
    double t1 = 1;
};

/** Part of segment [a, b] inside the closed triangle `tri` (either orientation), or
 *  nullopt if they do not meet. `tol` [m] widens the triangle slightly so that a beam
 *  running along a shared edge is kept by both neighbours rather than by neither. */
std::optional<SegmentInterval> clipSegmentToTriangle(
    const Eigen::Vector2d& a, const Eigen::Vector2d& b,
    const std::array<Eigen::Vector2d, 3>& tri, double tol = 1e-9);

/** Part of segment [a, b] inside the axis-aligned box [lo, hi] (Liang-Barsky). */
std::optional<SegmentInterval> clipSegmentToBox(
    const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& lo,
    const Eigen::Vector2d& hi);

/** True if the closed axis-aligned box [lo, hi] and the closed triangle share a point
 *  (separating-axis test on the two box axes and the three edge normals). */
bool boxIntersectsTriangle(
    const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
    const std::array<Eigen::Vector2d, 3>& tri);

/** True if `p` lies in the closed triangle (either orientation), up to `tol` [m]. */
bool triangleContains(
    const std::array<Eigen::Vector2d, 3>& tri, const Eigen::Vector2d& p, double tol = 1e-9);

/** Distance from `p` to segment [a, b]. */
double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

/** One hash key for a pair of signed 32-bit cell indices. The shift is done on unsigned
 *  values: shifting a negative signed integer is undefined behaviour. */
inline std::int64_t packCellKey(std::int64_t ix, std::int64_t iy)
{
    return static_cast<std::int64_t>((static_cast<std::uint64_t>(ix) << 32) ^
                                     (static_cast<std::uint64_t>(iy) & 0xffffffffULL));
}

/** packCellKey of the square cell of side `cell` holding `p`, shifted by (dx, dy) cells. */
inline std::int64_t pointCellKey(const Eigen::Vector2d& p, double cell, std::int64_t dx = 0, std::int64_t dy = 0)
{
    return packCellKey(static_cast<std::int64_t>(std::floor(p.x() / cell)) + dx,
                       static_cast<std::int64_t>(std::floor(p.y() / cell)) + dy);
}

}  // namespace hymm::dense
