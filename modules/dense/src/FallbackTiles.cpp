#include "hymm/dense/FallbackTiles.h"

#include "hymm/dense/geometry.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>
#include <limits>
#include <stdexcept>

namespace hymm::dense
{
FallbackTileKey fallbackTileOf(long anchor, const Eigen::Vector2d& p_ref, double tile_m)
{
    if (!(tile_m > 0)) throw std::invalid_argument("fallbackTileOf: tile_m must be > 0");
    if (!p_ref.allFinite()) throw std::invalid_argument("fallbackTileOf: point is not finite");
    FallbackTileKey k;
    k.anchor = anchor;
    const double fx = std::floor(p_ref.x() / tile_m), fy = std::floor(p_ref.y() / tile_m);
    // Tile indices are ints: a point that far (a nearly folded anchor's inverse map) has no tile.
    if (std::abs(fx) > 1e9 || std::abs(fy) > 1e9)
        throw std::invalid_argument("fallbackTileOf: point beyond the tile index range");
    k.ix = static_cast<int>(fx);
    k.iy = static_cast<int>(fy);
    // Half 0 holds the points below the diagonal (x - x0 >= y - y0), the diagonal included.
    k.half = (p_ref.x() - fx * tile_m) >= (p_ref.y() - fy * tile_m) ? 0 : 1;
    return k;
}

FallbackTileKey firstFallbackTileKey(long anchor)
{
    constexpr int lowest = std::numeric_limits<int>::min();
    return FallbackTileKey{anchor, lowest, lowest, lowest};
}

hymm::ltr::TriangleFrame::Vertices currentFallbackTileTriangle(
    const FallbackTileKey& key, double tile_m, const hymm::ltr::AffineRegionMap& to_current)
{
    auto tri = fallbackTileTriangle(key, tile_m);
    for (auto& v : tri) v = to_current.mapPoint(v);
    return tri;
}

hymm::ltr::TriangleFrame::Vertices fallbackTileTriangle(const FallbackTileKey& key, double tile_m)
{
    const Eigen::Vector2d o(key.ix * tile_m, key.iy * tile_m);
    const Eigen::Vector2d dx(tile_m, 0), dy(0, tile_m);
    if (key.half == 0) return {o, o + dx, o + dx + dy};
    return {o, o + dx + dy, o + dy};
}

double distanceToTriangle(const Eigen::Vector2d& p, const hymm::ltr::TriangleFrame::Vertices& tri)
{
    if (triangleContains(tri, p, 0.0)) return 0.0;
    return std::min({distanceToSegment(p, tri[0], tri[1]), distanceToSegment(p, tri[1], tri[2]),
                     distanceToSegment(p, tri[2], tri[0])});
}

std::optional<hymm::ltr::AffineRegionMap> usableReferenceToCurrent(
    const hymm::ltr::RegionPartition& partition, long id, FallbackFrame frame)
{
    if (!partition.has(id)) return std::nullopt;
    try
    {
        return fallbackFrameOf(partition.referenceToCurrent(id), partition.region(id).reference, frame);
    }
    catch (const std::invalid_argument&)
    {
        return std::nullopt;
    }
}

std::optional<long> nearestRegion(
    const hymm::ltr::RegionPartition& partition, const Eigen::Vector2d& p, double max_distance_m,
    const std::function<bool(long)>& usable)
{
    std::optional<long> best;
    double best_d = std::numeric_limits<double>::infinity();
    const Eigen::Vector2d r = Eigen::Vector2d::Constant(max_distance_m);
    for (const long id : partition.regionsInBox(p - r, p + r))
    {
        const double d = distanceToTriangle(p, partition.region(id).current);
        if (d > max_distance_m || d > best_d || (d == best_d && best && id > *best)) continue;
        if (usable && !usable(id)) continue;
        best = id;
        best_d = d;
    }
    return best;
}

std::optional<FallbackPlace> fallbackPlace(
    const hymm::ltr::RegionPartition& partition, const Eigen::Vector2d& p, double max_distance_m,
    double reuse_m, double tile_m, const std::function<const hymm::ltr::AffineRegionMap*(long)>& anchor_map,
    const std::function<bool(const FallbackTileKey&)>& tile_exists)
{
    // The nearest usable region, asking for a region's map only when it is nearer than the
    // best so far (reuse_m = 0 does no more than this).
    const auto usable = [&](long id) { return anchor_map(id) != nullptr; };
    const auto nearest = nearestRegion(partition, p, max_distance_m, usable);
    if (!nearest) return std::nullopt;
    const auto placeIn = [&](long id) {
        FallbackPlace f;
        f.anchor = id;
        f.p_ref = anchor_map(id)->inverseMapPoint(p);
        f.key = fallbackTileOf(id, f.p_ref, tile_m);
        return f;
    };
    if (!(reuse_m > 0)) return placeIn(*nearest);
    // Regions at most reuse_m farther than the nearest, by distance (ties: lowest id); the
    // search box is that reach, not max_distance_m.
    const double reach =
        std::min(max_distance_m, distanceToTriangle(p, partition.region(*nearest).current) + reuse_m);
    std::vector<std::pair<double, long>> near;
    const Eigen::Vector2d r = Eigen::Vector2d::Constant(reach);
    for (const long id : partition.regionsInBox(p - r, p + r))
    {
        const double d = distanceToTriangle(p, partition.region(id).current);
        if (d <= reach) near.emplace_back(d, id);
    }
    std::sort(near.begin(), near.end());
    for (const auto& [d, id] : near)
    {
        if (!usable(id)) continue;
        const FallbackPlace f = placeIn(id);
        if (tile_exists(f.key)) return f;
    }
    return placeIn(*nearest);
}

}  // namespace hymm::dense
