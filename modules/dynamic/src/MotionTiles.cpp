// The motion layers of the fallback tiles (HybridMetricMap's fallback, dense/FallbackTiles.h).
// A tile is differenced like a region (Sec. 6.3.1-6.3.2) under an id of its own, in its
// anchor's reference frame; only the look-ups that need its geometry live here.
#include <hymm/dense/OccupancyLayer.h>

#include <limits>

#include "hymm/dynamic/MotionDetector.h"

namespace hymm::dynamic
{
long MotionDetector::tileId(const dense::FallbackTileKey& key)
{
    const auto [it, made] = tile_ids_.emplace(key, next_tile_id_);
    if (made)
    {
        tile_keys_.emplace(next_tile_id_, key);
        ++next_tile_id_;
    }
    return it->second;
}

const dense::OccupancyLayer* MotionDetector::occupancyOf(const dense::HybridMetricMap& map, long id) const
{
    const dense::LocalDenseMap* local = nullptr;
    if (!isTile(id))
        local = map.localMap(id);
    else if (const auto key = tile_keys_.find(id); key != tile_keys_.end())
        local = map.fallbackMap(key->second);
    return local ? local->layerAs<dense::OccupancyLayer>(dense::OccupancyLayer::kKind) : nullptr;
}

MotionDetector::StepReport MotionDetector::step(
    const dense::HybridMetricMap& map, const std::vector<long>& regions_in_view,
    const std::vector<dense::FallbackTileKey>& tiles_in_view, double t)
{
    tile_m_ = map.options().fallback_tile_m;
    tile_frame_ = map.options().fallback_frame;
    tile_reach_m_ = map.fallbackReach();
    if (tiles_in_view.empty()) return step(map, regions_in_view, t);
    std::vector<long> ids = regions_in_view;
    ids.reserve(ids.size() + tiles_in_view.size());
    for (const auto& key : tiles_in_view)
        if (const auto* tile = map.fallbackMap(key); tile && tile->layer(dense::OccupancyLayer::kKind))
            ids.push_back(tileId(key));
    return step(map, ids, t);
}

const MotionLayer* MotionDetector::layer(MotionKind kind, const dense::FallbackTileKey& tile) const
{
    const auto it = tile_ids_.find(tile);
    return it == tile_ids_.end() ? nullptr : layer(kind, it->second);
}

std::optional<std::pair<ltr::TriangleFrame::Vertices, ltr::AffineRegionMap>> MotionDetector::frameOf(
    long id, const ltr::RegionPartition& partition) const
{
    if (!isTile(id))
    {
        if (!partition.has(id)) return std::nullopt;
        try
        {
            return std::make_pair(partition.region(id).current, partition.referenceToCurrent(id));
        }
        catch (const std::exception&)
        {
            return std::nullopt;  // a folded current triangle has no reference -> current map
        }
    }
    const auto key = tile_keys_.find(id);
    if (key == tile_keys_.end()) return std::nullopt;
    // The marks are cells of the dense map's tiles: the same frame as the map draws them in.
    const auto to_current = dense::usableReferenceToCurrent(partition, key->second.anchor, tile_frame_);
    if (!to_current) return std::nullopt;
    return std::make_pair(dense::currentFallbackTileTriangle(key->second, tile_m_, *to_current), *to_current);
}

void MotionDetector::noteTileMarks(long id, bool had_marks, bool has_marks)
{
    if (had_marks == has_marks) return;
    const long anchor = tile_keys_.at(id).anchor;
    if (has_marks)
        ++marked_tile_anchors_[anchor];
    else if (const auto it = marked_tile_anchors_.find(anchor); it != marked_tile_anchors_.end() && --it->second <= 0)
        marked_tile_anchors_.erase(it);
}

bool MotionDetector::tileMarked(const ltr::RegionPartition& partition, const Eigen::Vector2d& p, bool slow,
                                bool fast) const
{
    if (marked_tile_anchors_.empty() || !(tile_m_ > 0)) return false;
    const Eigen::Vector2d pad = Eigen::Vector2d::Constant(tile_reach_m_);
    for (const long anchor : partition.regionsInBox(p - pad, p + pad))
    {
        if (!marked_tile_anchors_.count(anchor)) continue;
        const auto to_current = dense::usableReferenceToCurrent(partition, anchor, tile_frame_);
        if (!to_current) continue;
        const Eigen::Vector2d r = to_current->inverseMapPoint(p);
        if (!r.allFinite() || (r.array().abs() > 1e9 * tile_m_).any()) continue;  // no tile index
        const auto it = tile_ids_.find(dense::fallbackTileOf(anchor, r, tile_m_));
        if (it == tile_ids_.end()) continue;
        const auto st = regions_.find(it->second);
        if (st == regions_.end()) continue;
        if ((slow && st->second.slow.count() > 0 && st->second.slow.at(r)) ||
            (fast && st->second.fast.count() > 0 && st->second.fast.at(r)))
            return true;
    }
    return false;
}

std::vector<ltr::TriangleFrame::Vertices> MotionDetector::markedTileTriangles(
    const ltr::RegionPartition& partition, const std::vector<long>& anchors) const
{
    std::vector<ltr::TriangleFrame::Vertices> out;
    for (const long anchor : anchors)
    {
        if (!marked_tile_anchors_.count(anchor)) continue;
        auto it = tile_ids_.lower_bound(dense::firstFallbackTileKey(anchor));
        for (; it != tile_ids_.end() && it->first.anchor == anchor; ++it)
            if (hasMarks(it->second))
                if (const auto frame = frameOf(it->second, partition)) out.push_back(frame->first);
    }
    return out;
}

}  // namespace hymm::dynamic
