#include "hymm/dense/HybridMetricMap.h"

#include "hymm/dense/LayerRegistry.h"

#include <algorithm>
#include <cmath>
#include <istream>
#include <limits>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <unordered_map>

namespace hymm::dense
{
namespace
{
using hymm::ltr::AffineRegionMap;
using hymm::ltr::RegionPartition;
using Vertices = hymm::ltr::TriangleFrame::Vertices;
}  // namespace

HybridMetricMap::HybridMetricMap(const Options& options)
    : options_(options), profiler_(options.enable_profiler, "hymm::HybridMetricMap")
{
    options_.validate();
}

std::unique_ptr<DenseLayer> HybridMetricMap::makeLayer(
    const std::string& kind, const Vertices& reference) const
{
    const LayerKind* k = findLayerKind(kind);
    return k && options_.*(k->enabled) ? k->make(options_, reference) : nullptr;
}

std::vector<std::string> HybridMetricMap::enabledKinds() const
{
    std::vector<std::string> out;
    for (const LayerKind& k : layerKinds())
        if (options_.*(k.enabled)) out.emplace_back(k.name);
    return out;
}

LocalDenseMap& HybridMetricMap::localMapFor(long region_id, const Vertices& reference)
{
    auto& slot = maps_[region_id];
    if (!slot)
    {
        slot = std::make_unique<LocalDenseMap>(region_id, reference);
        for (const std::string& kind : enabledKinds())
            if (auto layer = makeLayer(kind, reference)) slot->addLayer(std::move(layer));
        // With the fallback, a region must not hide what a fallback tile under it saw:
        // the tile holds the returns from before the region formed (and, as every tile,
        // all later ones), so the most occupied value wins there too.
        if (auto* occ = dynamic_cast<OccupancyLayer*>(slot->layer(OccupancyLayer::kKind));
            occ && options_.fallback_max_distance_m > 0)
            occ->setRenderMode(OccupancyLayer::RenderMode::MaxObserved);
    }
    return *slot;
}

LocalDenseMap& HybridMetricMap::fallbackMapFor(const FallbackTileKey& key)
{
    auto& slot = fallback_[key];
    if (!slot)
    {
        const Vertices reference = fallbackTileTriangle(key, options_.fallback_tile_m);
        slot = std::make_unique<LocalDenseMap>(key.anchor, reference);
        for (const std::string& kind : enabledKinds())
            if (auto layer = makeLayer(kind, reference)) slot->addLayer(std::move(layer));
        // Tiles of different anchors overlap: each draws only what it observed, the most
        // occupied value winning.
        if (auto* occ = dynamic_cast<OccupancyLayer*>(slot->layer(OccupancyLayer::kKind)))
            occ->setRenderMode(OccupancyLayer::RenderMode::MaxObserved);
    }
    return *slot;
}

void HybridMetricMap::forEachMap(
    const RegionPartition& partition, Content content,
    const std::function<void(const LocalDenseMap&, const AffineRegionMap&)>& fn) const
{
    if (content != Content::Regions)
    {
        long last = -1;
        std::optional<AffineRegionMap> to_current;
        for (const auto& [key, map] : fallback_)
        {
            if (key.anchor != last) to_current = fallbackToCurrent(partition, last = key.anchor);
            if (to_current) fn(*map, *to_current);
        }
    }
    if (content != Content::Fallback)
        for (const auto& [id, map] : maps_)
            if (const auto to_current = usableReferenceToCurrent(partition, id)) fn(*map, *to_current);
}

HybridMetricMap::CoarsenReport HybridMetricMap::coarsenIdleRegions()
{
    CoarsenReport rep;
    for (auto& [id, map] : maps_)
    {
        if (last_scan_regions_.count(id)) continue;
        auto* occ = dynamic_cast<OccupancyLayer*>(map->layer(OccupancyLayer::kKind));
        if (!occ || occ->isCoarse()) continue;
        ++rep.regions_checked;
        const size_t before = occ->memoryBytes();
        if (occ->coarsen()) rep.coarsened.push_back({id, before, occ->memoryBytes()});
    }
    return rep;
}

size_t HybridMetricMap::CoarsenReport::bytesBefore() const
{
    size_t n = 0;
    for (const auto& r : coarsened) n += r.bytes_before;
    return n;
}

size_t HybridMetricMap::CoarsenReport::bytesAfter() const
{
    size_t n = 0;
    for (const auto& r : coarsened) n += r.bytes_after;
    return n;
}

void HybridMetricMap::insertRegionScan(
    long region_id, const RegionScan& scan, const hymm::ltr::RegionPartition& partition)
{
    if (scan.empty()) return;
    localMapFor(region_id, partition.region(region_id).reference).insert(scan);
}

bool HybridMetricMap::insertFallbackReturn(
    const Eigen::Vector2d& sensor, const Eigen::Vector2d& ret, double range_std_m, double bearing_std_rad,
    const RegionPartition& partition)
{
    const double fb_dist = options_.fallback_max_distance_m;
    if (!(fb_dist > 0) || !ret.allFinite() || !sensor.allFinite()) return false;
    std::unordered_map<long, std::optional<AffineRegionMap>> maps;
    const auto place = fallbackPlace(
        partition, ret, fb_dist, options_.fallback_reuse_m, options_.fallback_tile_m,
        [&](long id) {
            const auto [it, fresh] = maps.try_emplace(id);
            if (fresh) it->second = fallbackToCurrent(partition, id);
            return it->second ? &*it->second : nullptr;
        },
        [&](const FallbackTileKey& k) { return fallback_.count(k) > 0; });
    if (!place) return false;
    const AffineRegionMap& to_current = *maps.at(place->anchor);
    const Eigen::Vector2d& p_ref = place->p_ref;
    RegionScan rs;
    rs.sensor = to_current.inverseMapPoint(sensor);
    rs.hits.push_back(p_ref);
    // A ray of zero length at the return: the occupancy layer marks its cell occupied and
    // nothing free.
    rs.rays.push_back(FreeRay{p_ref, p_ref, true});
    rs.range_std_m = range_std_m;
    rs.bearing_std_rad = bearing_std_rad;
    rs.to_reference_linear = to_current.inverse().linear();
    fallbackMapFor(place->key).insert(rs);
    return true;
}

std::vector<long> HybridMetricMap::removeStaleRegions(const RegionPartition& partition)
{
    std::vector<long> removed;
    for (auto it = maps_.begin(); it != maps_.end();)
    {
        if (partition.has(it->first))
        {
            ++it;
            continue;
        }
        removed.push_back(it->first);
        last_scan_regions_.erase(it->first);
        it = maps_.erase(it);
    }
    // Fallback content hangs off its anchor's frame: it goes with the anchor.
    for (auto it = fallback_.begin(); it != fallback_.end();)
        it = partition.has(it->first.anchor) ? std::next(it) : fallback_.erase(it);
    return removed;
}

std::vector<long> HybridMetricMap::removeRegions(const std::vector<long>& region_ids)
{
    std::vector<long> removed;
    for (const long id : region_ids)
    {
        if (maps_.erase(id)) removed.push_back(id);
        last_scan_regions_.erase(id);
        // Fallback content hangs off its anchor's frame: it goes with the anchor (the
        // tiles are ordered by anchor, so they are one range).
        const auto first = fallback_.lower_bound(firstFallbackTileKey(id));
        auto last = first;
        while (last != fallback_.end() && last->first.anchor == id) ++last;
        fallback_.erase(first, last);
    }
    return removed;
}

void HybridMetricMap::renderLayer(
    const std::string& kind, const RegionPartition& partition, mrpt::maps::CMetricMap& out,
    Content content) const
{
    core::TimedSection tle(profiler_, "dense.render." + kind);
    forEachMap(partition, content, [&](const LocalDenseMap& map, const AffineRegionMap& to_current) {
        if (const DenseLayer* layer = map.layer(kind)) layer->renderInto(to_current, out);
    });
}

void HybridMetricMap::renderPoints(
    const RegionPartition& partition, mrpt::maps::CSimplePointsMap& out, Content content) const
{
    out.clear();
    renderLayer(PointsLayer::kKind, partition, out, content);
}

void HybridMetricMap::renderOccupancy(
    const RegionPartition& partition, double resolution_m, mrpt::maps::COccupancyGridMap2D& out,
    Content content) const
{
    if (!(resolution_m > 0))
        throw std::invalid_argument("HybridMetricMap::renderOccupancy: resolution must be > 0");
    Eigen::Vector2d lo, hi;
    if (!layerBox(OccupancyLayer::kKind, partition, lo, hi, content))
        lo = hi = Eigen::Vector2d::Zero();  // nothing to draw
    out.setSize(
        static_cast<float>(lo.x() - resolution_m), static_cast<float>(hi.x() + resolution_m),
        static_cast<float>(lo.y() - resolution_m), static_cast<float>(hi.y() + resolution_m),
        static_cast<float>(resolution_m), 0.5f);
    renderLayer(OccupancyLayer::kKind, partition, out, content);
}

const LocalDenseMap* HybridMetricMap::localMap(long region_id) const
{
    const auto it = maps_.find(region_id);
    return it == maps_.end() ? nullptr : it->second.get();
}

const LocalDenseMap* HybridMetricMap::fallbackMap(const FallbackTileKey& key) const
{
    const auto it = fallback_.find(key);
    return it == fallback_.end() ? nullptr : it->second.get();
}

std::vector<FallbackTileKey> HybridMetricMap::fallbackTileKeys() const
{
    std::vector<FallbackTileKey> out;
    out.reserve(fallback_.size());
    for (const auto& kv : fallback_) out.push_back(kv.first);
    return out;
}

std::vector<FallbackTileKey> HybridMetricMap::fallbackTilesInBox(
    const RegionPartition& partition, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) const
{
    std::vector<FallbackTileKey> out;
    if (fallback_.empty()) return out;
    const Eigen::Vector2d pad = Eigen::Vector2d::Constant(fallbackReach());
    const Eigen::Vector2d lo_pad = lo - pad, hi_pad = hi + pad;
    for (const long anchor : partition.regionsInBox(lo_pad, hi_pad))
    {
        // The grid lists a region in whole cells: its own box first, then its tiles.
        const auto& cur = partition.region(anchor).current;
        const Eigen::Vector2d alo = cur[0].cwiseMin(cur[1]).cwiseMin(cur[2]);
        const Eigen::Vector2d ahi = cur[0].cwiseMax(cur[1]).cwiseMax(cur[2]);
        if ((alo.array() > hi_pad.array()).any() || (ahi.array() < lo_pad.array()).any()) continue;
        auto it = fallback_.lower_bound(firstFallbackTileKey(anchor));
        if (it == fallback_.end() || it->first.anchor != anchor) continue;
        const auto to_current = fallbackToCurrent(partition, anchor);
        if (!to_current) continue;
        for (; it != fallback_.end() && it->first.anchor == anchor; ++it)
        {
            const auto t = currentFallbackTileTriangle(it->first, options_.fallback_tile_m, *to_current);
            const Eigen::Vector2d tlo = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
            const Eigen::Vector2d thi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
            if ((tlo.array() <= hi.array()).all() && (thi.array() >= lo.array()).all()) out.push_back(it->first);
        }
    }
    return out;
}

double HybridMetricMap::fallbackReach() const
{
    // A return within fallback_max_distance_m of the anchor's triangle when kept, plus its
    // tile's diagonal; a quarter more for the anchor's later deformation (the affine map
    // stretches the reference plane by the change of the triangle's shape).
    return 1.25 * (options_.fallback_max_distance_m + std::sqrt(2.0) * options_.fallback_tile_m);
}

std::vector<long> HybridMetricMap::regionIds() const
{
    std::vector<long> out;
    for (const auto& kv : maps_) out.push_back(kv.first);
    return out;
}

size_t HybridMetricMap::memoryBytes() const
{
    size_t n = sizeof(*this);
    for (const auto& kv : maps_) n += kv.second->memoryBytes() + 4 * sizeof(void*);
    for (const auto& kv : fallback_) n += kv.second->memoryBytes() + sizeof(kv.first) + 4 * sizeof(void*);
    return n;
}

std::map<std::string, size_t> HybridMetricMap::memoryBytesByKind() const
{
    std::map<std::string, size_t> out;
    for (const auto& kv : maps_)
        for (const std::string& kind : kv.second->layerKinds()) out[kind] += kv.second->layer(kind)->memoryBytes();
    for (const auto& kv : fallback_)
        for (const std::string& kind : kv.second->layerKinds()) out[kind] += kv.second->layer(kind)->memoryBytes();
    return out;
}

void HybridMetricMap::save(std::ostream& out) const
{
    out << "hybrid_metric_map " << maps_.size() << '\n';
    for (const auto& kv : maps_) kv.second->save(out);
}

void HybridMetricMap::load(std::istream& in)
{
    std::string tag;
    size_t n = 0;
    if (!(in >> tag >> n) || tag != "hybrid_metric_map")
        throw std::runtime_error("HybridMetricMap::load: expected 'hybrid_metric_map <count>'");
    const LocalDenseMap::LayerFactory factory = [this](const std::string& kind, const Vertices& ref) {
        return makeLayer(kind, ref);
    };
    std::map<long, std::unique_ptr<LocalDenseMap>> maps;
    for (size_t i = 0; i < n; ++i)
    {
        auto m = LocalDenseMap::load(in, factory);
        const long id = m->regionId();
        if (!maps.emplace(id, std::move(m)).second)
            throw std::runtime_error("HybridMetricMap::load: region " + std::to_string(id) + " twice");
    }
    maps_ = std::move(maps);
    last_scan_regions_.clear();
}

}  // namespace hymm::dense
