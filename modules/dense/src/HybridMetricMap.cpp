#include "hymm/dense/HybridMetricMap.h"

#include "hymm/dense/geometry.h"

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

// A clipped beam whose far end is within this fraction of the whole beam from the
// return still ends at the return (rounding in the clip parameter).
constexpr double kEndParamTol = 1e-9;

/** A region the scan may touch, with its current frame. */
struct Candidate
{
    long id;
    Vertices reference;  // the region's reference triangle (a fallback tile's triangle)
    AffineRegionMap to_current;
    Eigen::Vector2d lo, hi;  // current bounding box
    bool withheld = false;   // refused by insertScan's `accept`
};

bool boxesOverlap(
    const Eigen::Vector2d& alo, const Eigen::Vector2d& ahi, const Eigen::Vector2d& blo,
    const Eigen::Vector2d& bhi)
{
    return alo.x() <= bhi.x() && blo.x() <= ahi.x() && alo.y() <= bhi.y() && blo.y() <= ahi.y();
}

/** Beam pieces of `w` inside candidate `c`, in its reference frame. With
 *  `shadow_margin` >= 0 also the returns of beams that end before the region but whose
 *  line goes on into its bounding box grown by the margin (RegionScan::shadow_returns). */
void clipBeams(const WorldScan& w, const Candidate& c, RegionScan& rs, double shadow_margin)
{
    const Vertices& ref = c.reference;
    rs.sensor = c.to_current.inverseMapPoint(w.sensor);
    const bool shadows = shadow_margin >= 0;
    const Eigen::Vector2d glo = c.lo.array() - shadow_margin, ghi = c.hi.array() + shadow_margin;
    // Farthest the grown box gets from the sensor: a beam line is followed up to there.
    const Eigen::Vector2d far_corner = (glo - w.sensor).cwiseAbs().cwiseMax((ghi - w.sensor).cwiseAbs());
    const double reach = far_corner.norm();
    for (const WorldBeam& b : w.beams)
    {
        if (boxesOverlap(w.sensor.cwiseMin(b.end), w.sensor.cwiseMax(b.end), c.lo, c.hi))
        {
            const Eigen::Vector2d e_ref = c.to_current.inverseMapPoint(b.end);
            const auto iv = clipSegmentToTriangle(rs.sensor, e_ref, ref);
            if (iv)
            {
                const Eigen::Vector2d d = e_ref - rs.sensor;
                const bool to_end = iv->t1 >= 1.0 - kEndParamTol;
                FreeRay ray{rs.sensor + iv->t0 * d, to_end ? e_ref : Eigen::Vector2d(rs.sensor + iv->t1 * d),
                            b.hit && to_end};
                ray.beam_end = e_ref;  // the layers' beam model needs the whole beam's range
                ray.beam_hit = b.hit;
                rs.rays.push_back(ray);
                continue;
            }
        }
        if (!shadows || !b.hit) continue;
        // Does the beam's line, past its return, go on into the region (grown box)?
        const Eigen::Vector2d d = b.end - w.sensor;
        const double len = d.norm();
        if (!(len > 0) || reach <= len) continue;
        if (clipSegmentToBox(b.end, w.sensor + d * (reach / len), glo, ghi))
            rs.shadow_returns.push_back(c.to_current.inverseMapPoint(b.end));
    }
}
}  // namespace

HybridMetricMap::HybridMetricMap(const Options& options)
    : options_(options), profiler_(options.enable_profiler, "hymm::HybridMetricMap")
{
    options_.validate();
}

std::unique_ptr<DenseLayer> HybridMetricMap::makeLayer(
    const std::string& kind, const Vertices& reference) const
{
    if (kind == PointsLayer::kKind && options_.enable_points)
        return std::make_unique<PointsLayer>(options_.points, reference);
    if (kind == OccupancyLayer::kKind && options_.enable_occupancy)
        return std::make_unique<OccupancyLayer>(options_.occupancy, reference);
    if (kind == ParticlesLayer::kKind && options_.enable_particles)
        return std::make_unique<ParticlesLayer>(options_.particles, reference);
    if (kind == SogLayer::kKind && options_.enable_sog) return std::make_unique<SogLayer>(options_.sog);
    if (kind == PropertyLayer::kKind && options_.enable_property)
        return std::make_unique<PropertyLayer>(options_.property, reference);
    return nullptr;
}

std::vector<std::string> HybridMetricMap::enabledKinds() const
{
    std::vector<std::string> out;
    const std::pair<const char*, bool> all[] = {
        {PointsLayer::kKind, options_.enable_points},       {OccupancyLayer::kKind, options_.enable_occupancy},
        {ParticlesLayer::kKind, options_.enable_particles}, {SogLayer::kKind, options_.enable_sog},
        {PropertyLayer::kKind, options_.enable_property}};
    for (const auto& [kind, on] : all)
        if (on) out.emplace_back(kind);
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
    const auto current = [&](long id) -> std::optional<AffineRegionMap> {
        if (!partition.has(id)) return std::nullopt;
        try
        {
            return partition.referenceToCurrent(id);
        }
        catch (const std::invalid_argument&)
        {
            return std::nullopt;  // degenerate current triangle: no valid position for its content
        }
    };
    if (content != Content::Regions)
    {
        long last = -1;
        std::optional<AffineRegionMap> to_current;
        for (const auto& [key, map] : fallback_)
        {
            if (key.anchor != last) to_current = current(last = key.anchor);
            if (to_current) fn(*map, *to_current);
        }
    }
    if (content != Content::Fallback)
        for (const auto& [id, map] : maps_)
            if (const auto to_current = current(id)) fn(*map, *to_current);
}

HybridMetricMap::InsertStats HybridMetricMap::insertScan(
    const ScanPoints& scan, const mrpt::math::TPose2D& vehicle_pose, const RegionPartition& partition,
    const RegionFilter& accept)
{
    mrpt::system::CTimeLoggerEntry tle(profiler_, "dense.insertScan");
    scan.validate();  // values / noise: bad input is rejected before anything changes
    InsertStats st;
    const WorldScan w = scan.toWorld(vehicle_pose, options_.max_range_m, options_.no_return_free_range_m);
    st.beams = w.beams.size();
    st.beyond_range = w.beyond_range;
    st.no_return = w.no_return;

    // 1. Regions near the scan, with their reference -> current maps.
    std::vector<Candidate> cands;
    std::unordered_map<long, size_t> index_of;
    {
        mrpt::system::CTimeLoggerEntry t1(profiler_, "dense.insertScan.1_regions");
        for (const long id : partition.regionsInBox(w.lo, w.hi))
        {
            const auto& r = partition.region(id);
            try
            {
                Candidate c{id, r.reference, partition.referenceToCurrent(id), {}, {}, false};
                c.lo = r.current[0].cwiseMin(r.current[1]).cwiseMin(r.current[2]);
                c.hi = r.current[0].cwiseMax(r.current[1]).cwiseMax(r.current[2]);
                if (accept && !accept(id))
                {
                    c.withheld = true;
                    ++st.regions_withheld;
                }
                index_of[id] = cands.size();
                cands.push_back(std::move(c));
            }
            catch (const std::invalid_argument&)
            {
                ++st.regions_degenerate;  // the filter folded this triangle: no frame
            }
        }
        st.regions_visited = cands.size() + st.regions_degenerate;
    }

    // 2. Owner of each return: one region (lowest id on shared borders); a return in no
    // region goes to a fallback tile of the nearest usable region when the fallback is on.
    std::vector<RegionScan> per_region(cands.size());
    const double fb_dist = options_.fallback_max_distance_m;
    std::map<FallbackTileKey, RegionScan> fb_hits;
    std::unordered_map<long, std::optional<AffineRegionMap>> anchor_maps;  // nullopt: unusable
    const auto anchorMap = [&](long id) -> const std::optional<AffineRegionMap>& {
        const auto [it, fresh] = anchor_maps.try_emplace(id);
        if (fresh)
        {
            const auto c = index_of.find(id);
            if (c != index_of.end())
            {
                if (!cands[c->second].withheld) it->second = cands[c->second].to_current;
            }
            else if (!accept || accept(id))
                it->second = usableReferenceToCurrent(partition, id);
        }
        return it->second;
    };
    // Keeps return b in a fallback tile of the nearest usable region; false if none is near.
    const auto keepInFallback = [&](const WorldBeam& b) {
        if (!(fb_dist > 0)) return false;
        const auto anchor =
            nearestRegion(partition, b.end, fb_dist, [&](long id) { return anchorMap(id).has_value(); });
        if (!anchor) return false;
        const Eigen::Vector2d p_ref = anchorMap(*anchor)->inverseMapPoint(b.end);
        RegionScan& rs = fb_hits[fallbackTileOf(*anchor, p_ref, options_.fallback_tile_m)];
        rs.hits.push_back(p_ref);
        if (!scan.values.empty()) rs.hit_values.push_back(scan.values[b.source]);
        if (!scan.value_stds.empty()) rs.hit_value_stds.push_back(scan.value_stds[b.source]);
        return true;
    };
    {
        mrpt::system::CTimeLoggerEntry t2(profiler_, "dense.insertScan.2_assign");
        for (const WorldBeam& b : w.beams)
        {
            if (!b.hit) continue;
            const auto owner = partition.findRegion(b.end);
            const auto it = owner ? index_of.find(*owner) : index_of.end();
            if (it == index_of.end())
            {
                ++st.returns_outside;
                st.unassigned.push_back(b.end);
                const bool kept = keepInFallback(b);
                st.returns_fallback += kept;
                st.unassigned_kept.push_back(kept);
                continue;
            }
            if (cands[it->second].withheld)
            {
                ++st.returns_withheld;
                st.withheld.push_back(b.end);
                // The owner's frame is not known well enough now; a usable region nearby is.
                const bool kept = keepInFallback(b);
                st.withheld_fallback += kept;
                st.withheld_kept.push_back(kept);
                continue;
            }
            RegionScan& rs = per_region[it->second];
            rs.hits.push_back(cands[it->second].to_current.inverseMapPoint(b.end));
            if (!scan.values.empty()) rs.hit_values.push_back(scan.values[b.source]);
            if (!scan.value_stds.empty()) rs.hit_value_stds.push_back(scan.value_stds[b.source]);
            ++st.returns_stored;
        }
    }

    // 3. Split the beams among the regions and fuse into every layer (Sec. 4.5).
    {
        mrpt::system::CTimeLoggerEntry t3(profiler_, "dense.insertScan.3_clip_fuse");
        last_scan_regions_.clear();
        // The particle layer's free-space protection needs the returns a region hides
        // behind (ParticlesLayer step 4); no other layer reads them.
        const double shadow_margin =
            options_.enable_particles && options_.particles.free_space_update && options_.particles.free_space_protection
                ? options_.particles.d_min_m
                : -1.0;
        for (size_t k = 0; k < cands.size(); ++k)
        {
            if (cands[k].withheld) continue;
            RegionScan& rs = per_region[k];
            clipBeams(w, cands[k], rs, shadow_margin);
            if (rs.empty()) continue;
            rs.range_std_m = scan.range_std_m;
            rs.bearing_std_rad = scan.bearing_std_rad;
            rs.to_reference_linear = cands[k].to_current.inverse().linear();
            localMapFor(cands[k].id, cands[k].reference).insert(rs);
            last_scan_regions_.insert(cands[k].id);
            ++st.regions_updated;
        }
    }

    // 3b. Fallback tiles near the scan: the new returns, and the free space of every beam
    // crossing a tile (existing tiles too, so that their cells can be revised).
    if (fb_dist > 0)
    {
        mrpt::system::CTimeLoggerEntry t3b(profiler_, "dense.insertScan.3b_fallback");
        const double shadow_margin = -1.0;
        std::set<long> anchors;
        for (const auto& kv : fb_hits) anchors.insert(kv.first.anchor);
        const Eigen::Vector2d reach = Eigen::Vector2d::Constant(fb_dist + 2.0 * options_.fallback_tile_m);
        for (const long id : partition.regionsInBox(w.lo - reach, w.hi + reach))
            if (fallback_.lower_bound(FallbackTileKey{id, std::numeric_limits<int>::min(), 0, 0}) !=
                fallback_.lower_bound(FallbackTileKey{id + 1, std::numeric_limits<int>::min(), 0, 0}))
                anchors.insert(id);
        for (const long id : anchors)
        {
            const auto& to_current = anchorMap(id);
            if (!to_current) continue;  // withheld or folded anchor: its tiles wait
            std::set<FallbackTileKey> keys;
            for (auto it = fallback_.lower_bound(FallbackTileKey{id, std::numeric_limits<int>::min(), 0, 0});
                 it != fallback_.end() && it->first.anchor == id; ++it)
                keys.insert(it->first);
            for (auto it = fb_hits.lower_bound(FallbackTileKey{id, std::numeric_limits<int>::min(), 0, 0});
                 it != fb_hits.end() && it->first.anchor == id; ++it)
                keys.insert(it->first);
            for (const FallbackTileKey& key : keys)
            {
                Candidate c{id, fallbackTileTriangle(key, options_.fallback_tile_m), *to_current, {}, {}, false};
                Vertices cur;
                for (size_t v = 0; v < 3; ++v) cur[v] = c.to_current.mapPoint(c.reference[v]);
                c.lo = cur[0].cwiseMin(cur[1]).cwiseMin(cur[2]);
                c.hi = cur[0].cwiseMax(cur[1]).cwiseMax(cur[2]);
                if (!boxesOverlap(c.lo, c.hi, w.lo, w.hi)) continue;
                RegionScan rs;
                if (const auto h = fb_hits.find(key); h != fb_hits.end()) rs = std::move(h->second);
                clipBeams(w, c, rs, shadow_margin);
                // A ray ending in the tile at a return that a region or another tile owns
                // stays a hit here: the tile's cells then see every return as they see
                // every beam's free space (the returns' points, particles and Gaussians
                // stay with their owner alone). Marking that cell free instead wore down
                // the walls of overlapping tiles whose returns went elsewhere (ch4: the
                // cells of most outline the classic grid covers and HYMM's points hold
                // stayed at P <= 0.8).
                if (rs.empty()) continue;
                rs.range_std_m = scan.range_std_m;
                rs.bearing_std_rad = scan.bearing_std_rad;
                rs.to_reference_linear = c.to_current.inverse().linear();
                fallbackMapFor(key).insert(rs);
            }
        }
    }

    // 4. Background coarsening of idle, almost-empty regions (Sec. 4.1.3), if due.
    ++scans_;
    if (options_.coarsen_every_n_scans > 0 && scans_ % static_cast<size_t>(options_.coarsen_every_n_scans) == 0)
    {
        mrpt::system::CTimeLoggerEntry t4(profiler_, "dense.insertScan.4_coarsen");
        st.regions_coarsened = coarsenIdleRegions().coarsened.size();
    }
    return st;
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
    const auto anchor = nearestRegion(partition, ret, fb_dist, [&](long id) {
        return usableReferenceToCurrent(partition, id).has_value();
    });
    if (!anchor) return false;
    const AffineRegionMap to_current = *usableReferenceToCurrent(partition, *anchor);
    const Eigen::Vector2d p_ref = to_current.inverseMapPoint(ret);
    RegionScan rs;
    rs.sensor = to_current.inverseMapPoint(sensor);
    rs.hits.push_back(p_ref);
    // A ray of zero length at the return: the occupancy layer marks its cell occupied and
    // nothing free.
    rs.rays.push_back(FreeRay{p_ref, p_ref, true});
    rs.range_std_m = range_std_m;
    rs.bearing_std_rad = bearing_std_rad;
    rs.to_reference_linear = to_current.inverse().linear();
    fallbackMapFor(fallbackTileOf(*anchor, p_ref, options_.fallback_tile_m)).insert(rs);
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
        const auto first = fallback_.lower_bound(FallbackTileKey{id, std::numeric_limits<int>::min(), 0, 0});
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
    mrpt::system::CTimeLoggerEntry tle(profiler_, "dense.render." + kind);
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
