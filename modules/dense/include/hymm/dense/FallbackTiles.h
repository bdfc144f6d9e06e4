/**
 * @file FallbackTiles.h
 * @brief Where a laser return that no Local Triangular Region holds is kept when the
 *        fallback of HybridMetricMap is on (Options::fallback_max_distance_m > 0).
 *
 * A return can lie beyond every triangle the partition can build (objects past the outer
 * landmarks, far returns beside a sparse row of trees), or in an area no region reached
 * yet. The thesis drops it (or keeps it in the delayed store until a region forms, Sec.
 * 3.7.3). The fallback keeps it in the frame of the NEAREST region (the anchor): its
 * position is written in the anchor's reference frame, i.e. in the local coordinates of
 * Eq. 3.3 extended beyond the triangle (coordinates outside [0, 1]), and rendered through
 * the anchor's reference -> current affine map like the anchor's own content. The
 * extrapolation amplifies the error of the anchor's vertices with the distance from the
 * triangle (a vertex error e moves a point at distance d from a triangle of size s by
 * about e (1 + d / s)), which is why the distance is bounded and why the fallback's
 * content is scored apart (metrics.json "fallback"). FallbackFrame::Rigid renders it
 * through the rotation and translation fitted to the anchor's vertices instead, so only
 * the rigid part of the anchor's correction is extrapolated.
 *
 * Storage: the anchor's reference plane is cut into square tiles of side `tile_m`, each
 * split along its diagonal into two triangles; each triangle holding a return is a
 * LocalDenseMap with every enabled layer (bounded grids, no unbounded extrapolated grid).
 *
 * Tiles of different anchors overlap where their anchors are near the same place, and
 * every tile a beam crosses ray-casts its free space, so the cost of a scan grows with
 * the anchors that keep tiles there. With a reuse distance (fallbackPlace) a return goes
 * to a tile that already holds its position when that tile's anchor is at most the reuse
 * distance farther than the nearest one: the tiles then cover a place about once.
 */
#pragma once

#include <hymm/ltr/RegionPartition.h>
#include <hymm/ltr/TriangleFrame.h>

#include <Eigen/Core>

#include <functional>
#include <optional>
#include <tuple>

namespace hymm::dense
{
/** One fallback triangle: anchor region, tile (ix, iy) of side tile_m in the anchor's
 *  reference frame, half 0 (below the diagonal from the tile's lower-left corner) or 1. */
struct FallbackTileKey
{
    long anchor = -1;
    int ix = 0, iy = 0, half = 0;
    bool operator<(const FallbackTileKey& o) const
    {
        return std::tie(anchor, ix, iy, half) < std::tie(o.anchor, o.ix, o.iy, o.half);
    }
    bool operator==(const FallbackTileKey& o) const
    {
        return anchor == o.anchor && ix == o.ix && iy == o.iy && half == o.half;
    }
};

/** The tile triangle holding reference point `p_ref` of `anchor`. Throws
 *  std::invalid_argument if tile_m <= 0, p_ref is not finite or beyond 1e9 tiles. */
FallbackTileKey fallbackTileOf(long anchor, const Eigen::Vector2d& p_ref, double tile_m);

/** Vertices of the tile triangle (counter-clockwise, anchor's reference frame). */
hymm::ltr::TriangleFrame::Vertices fallbackTileTriangle(const FallbackTileKey& key, double tile_m);

/** The same mapped to the current estimates through the anchor's reference -> current map. */
hymm::ltr::TriangleFrame::Vertices currentFallbackTileTriangle(
    const FallbackTileKey& key, double tile_m, const hymm::ltr::AffineRegionMap& to_current);

/** The smallest key of `anchor`'s tiles: containers ordered by key hold an anchor's tiles
 *  as one range starting at lower_bound(firstFallbackTileKey(anchor)). */
FallbackTileKey firstFallbackTileKey(long anchor);

/** Euclidean distance from `p` to the closed triangle `tri` (0 inside). */
double distanceToTriangle(const Eigen::Vector2d& p, const hymm::ltr::TriangleFrame::Vertices& tri);

/** How fallback content follows its anchor's vertices. */
enum class FallbackFrame
{
    /** The anchor's affine map (Eq. 3.3 extended beyond the triangle): the triangle's
     *  deformation is extrapolated too, by (1 + d / s) at distance d. */
    Affine,
    /** The rotation and translation that fit the anchor's three vertex pairs best
     *  (AffineRegionMap::rigidPart): a rigid correction of the anchor moves the content
     *  exactly as Affine does; its deformation (shear, scale) is not extrapolated, though
     *  independent vertex errors still move the fitted rotation, whose effect grows with
     *  the distance from the triangle. */
    Rigid,
};

/** The region's reference-to-current map (its rigid part with FallbackFrame::Rigid), or
 *  nullopt when the partition lacks it or its current triangle is degenerate
 *  (RegionPartition::referenceToCurrent refuses it): such a region anchors no fallback
 *  content this scan. */
std::optional<hymm::ltr::AffineRegionMap> usableReferenceToCurrent(
    const hymm::ltr::RegionPartition& partition, long id, FallbackFrame frame = FallbackFrame::Affine);

/** `region_map` (built from the region's `reference` vertices) as fallback content
 *  follows it. */
inline hymm::ltr::AffineRegionMap fallbackFrameOf(
    const hymm::ltr::AffineRegionMap& region_map, const hymm::ltr::TriangleFrame::Vertices& reference,
    FallbackFrame frame)
{
    return frame == FallbackFrame::Rigid ? region_map.rigidPart(reference) : region_map;
}

/** The region whose CURRENT triangle is nearest to `p` within `max_distance_m` (ties:
 *  lowest id) among those `usable` accepts, or nullopt. Only regions whose box meets the
 *  square of half-side max_distance_m around p are visited (RegionPartition lookup grid). */
std::optional<long> nearestRegion(
    const hymm::ltr::RegionPartition& partition, const Eigen::Vector2d& p, double max_distance_m,
    const std::function<bool(long)>& usable = {});

/** Where fallbackPlace() keeps a return. */
struct FallbackPlace
{
    long anchor = -1;
    FallbackTileKey key;
    Eigen::Vector2d p_ref;  //!< the return in the anchor's reference frame
};

/** The tile that keeps return `p`: among the regions whose current triangle is within
 *  `max_distance_m` of p and whose map `anchor_map` gives (nullptr: unusable), the nearest
 *  one's tile holding p; but when a region at most `reuse_m` farther than the nearest
 *  already has a tile holding p (`tile_exists`), the nearest such region's tile (ties:
 *  lowest id). reuse_m = 0: always the nearest region's tile. nullopt when no
 *  usable region is near. Regions are found through the partition's lookup grid. */
std::optional<FallbackPlace> fallbackPlace(
    const hymm::ltr::RegionPartition& partition, const Eigen::Vector2d& p, double max_distance_m,
    double reuse_m, double tile_m,
    const std::function<const hymm::ltr::AffineRegionMap*(long)>& anchor_map,
    const std::function<bool(const FallbackTileKey&)>& tile_exists);

}  // namespace hymm::dense
