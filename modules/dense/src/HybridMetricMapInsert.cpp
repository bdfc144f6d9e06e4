/**
 * @file HybridMetricMapInsert.cpp
 * @brief HybridMetricMap::insertScan (Sec. 4.5): the regions near a scan, the owner of
 *        each return, the beams clipped to every region and to the fallback tiles.
 */
#include "hymm/dense/HybridMetricMap.h"

#include "hymm/dense/geometry.h"

#include <limits>
#include <optional>
#include <set>
#include <stdexcept>
#include <unordered_map>
#include <utility>

namespace hymm::dense
{
namespace
{
using hymm::ltr::AffineRegionMap;
using hymm::ltr::RegionPartition;
using Vertices = hymm::ltr::TriangleFrame::Vertices;
using InsertStats = HybridMetricMap::InsertStats;

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
/** The first key of `anchor`'s tiles in a map ordered by FallbackTileKey. */
FallbackTileKey firstTileOf(long anchor)
{
    return FallbackTileKey{anchor, std::numeric_limits<int>::min(), 0, 0};
}

/** The regions a scan may touch (step 1 of insertScan) and the owner of each of its
 *  returns (step 2); the frames of fallback anchors are looked up once per scan. */
class ScanOwners
{
   public:
    ScanOwners(const RegionPartition& partition, const HybridMetricMap::RegionFilter& accept,
               const std::map<FallbackTileKey, std::unique_ptr<LocalDenseMap>>& tiles, FallbackFrame frame)
        : partition_(partition), accept_(accept), tiles_(tiles), frame_(frame)
    {
    }

    std::vector<Candidate> cands;
    std::vector<RegionScan> per_region;             // parallel to cands: their returns
    std::map<FallbackTileKey, RegionScan> fb_hits;  // returns kept by the fallback

    /** Regions near the scan, with their reference -> current maps. */
    void collectRegions(const WorldScan& w, InsertStats& st)
    {
        for (const long id : partition_.regionsInBox(w.lo, w.hi))
        {
            const auto& r = partition_.region(id);
            try
            {
                Candidate c{id, r.reference, partition_.referenceToCurrent(id), {}, {}, false};
                c.lo = r.current[0].cwiseMin(r.current[1]).cwiseMin(r.current[2]);
                c.hi = r.current[0].cwiseMax(r.current[1]).cwiseMax(r.current[2]);
                if (accept_ && !accept_(id))
                {
                    c.withheld = true;
                    ++st.regions_withheld;
                }
                index_of_[id] = cands.size();
                cands.push_back(std::move(c));
            }
            catch (const std::invalid_argument&)
            {
                ++st.regions_degenerate;  // the filter folded this triangle: no frame
            }
        }
        st.regions_visited = cands.size() + st.regions_degenerate;
    }

    /** Owner of each return: one region (lowest id on shared borders); a return in no
     *  region goes to a fallback tile of the nearest usable region when the fallback is on
     *  (fb_dist > 0). */
    void assignReturns(
        const WorldScan& w, const ScanPoints& scan, const HybridMetricMap::Options& o, InsertStats& st)
    {
        per_region.resize(cands.size());
        for (const WorldBeam& b : w.beams)
        {
            if (!b.hit) continue;
            const auto owner = partition_.findRegion(b.end);
            const auto it = owner ? index_of_.find(*owner) : index_of_.end();
            if (it == index_of_.end())
            {
                ++st.returns_outside;
                st.unassigned.push_back(b.end);
                st.unassigned_source.push_back(b.source);
                const bool kept = keepInFallback(b, scan, o);
                st.returns_fallback += kept;
                st.unassigned_kept.push_back(kept);
                continue;
            }
            if (cands[it->second].withheld)
            {
                ++st.returns_withheld;
                st.withheld.push_back(b.end);
                // The owner's frame is not known well enough now; a usable region nearby is.
                const bool kept = keepInFallback(b, scan, o);
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

    /** The current frame of region `id` as a fallback anchor; nullopt when it is
     *  withheld or its triangle is folded. */
    const std::optional<AffineRegionMap>& anchorMap(long id)
    {
        const auto [it, fresh] = anchor_maps_.try_emplace(id);
        if (fresh)
        {
            const auto c = index_of_.find(id);
            if (c != index_of_.end())
            {
                if (const Candidate& cand = cands[c->second]; !cand.withheld)
                    it->second = fallbackFrameOf(cand.to_current, cand.reference, frame_);
            }
            else if (!accept_ || accept_(id))
                it->second = usableReferenceToCurrent(partition_, id, frame_);
        }
        return it->second;
    }

   private:
    /** Keeps return b in a fallback tile (fallbackPlace); false if no usable region is near. */
    bool keepInFallback(const WorldBeam& b, const ScanPoints& scan, const HybridMetricMap::Options& o)
    {
        if (!(o.fallback_max_distance_m > 0)) return false;
        const auto place = fallbackPlace(
            partition_, b.end, o.fallback_max_distance_m, o.fallback_reuse_m, o.fallback_tile_m,
            [&](long id) {
                const auto& m = anchorMap(id);
                return m ? &*m : nullptr;
            },
            [&](const FallbackTileKey& k) { return tiles_.count(k) > 0 || fb_hits.count(k) > 0; });
        if (!place) return false;
        RegionScan& rs = fb_hits[place->key];
        rs.hits.push_back(place->p_ref);
        if (!scan.values.empty()) rs.hit_values.push_back(scan.values[b.source]);
        if (!scan.value_stds.empty()) rs.hit_value_stds.push_back(scan.value_stds[b.source]);
        return true;
    }

    const RegionPartition& partition_;
    const HybridMetricMap::RegionFilter& accept_;
    const std::map<FallbackTileKey, std::unique_ptr<LocalDenseMap>>& tiles_;
    const FallbackFrame frame_;
    std::unordered_map<long, size_t> index_of_;  // region id -> index in cands
    std::unordered_map<long, std::optional<AffineRegionMap>> anchor_maps_;  // nullopt: unusable
};

/** Margin of RegionScan::shadow_returns, -1 for none: the particle layer's free-space
 *  protection needs the returns a region hides behind (ParticlesLayer step 4); no other
 *  layer reads them. */
double shadowMargin(const HybridMetricMap::Options& o)
{
    return o.enable_particles && o.particles.free_space_update && o.particles.free_space_protection
               ? o.particles.d_min_m
               : -1.0;
}

/** Clips the beams to every region the scan may update (beside the returns it owns) and
 *  returns the indices of those that get something, ascending. */
std::vector<size_t> clipToRegions(
    const WorldScan& w, const ScanPoints& scan, ScanOwners& owners, double shadow_margin)
{
    std::vector<size_t> updated;
    for (size_t k = 0; k < owners.cands.size(); ++k)
    {
        const Candidate& c = owners.cands[k];
        if (c.withheld) continue;
        RegionScan& rs = owners.per_region[k];
        clipBeams(w, c, rs, shadow_margin);
        if (rs.empty()) continue;
        rs.range_std_m = scan.range_std_m;
        rs.bearing_std_rad = scan.bearing_std_rad;
        rs.to_reference_linear = c.to_current.inverse().linear();
        updated.push_back(k);
    }
    return updated;
}

/** The fallback tiles near the scan that get something from it, each with its returns
 *  and the beam pieces crossing it (existing tiles too, so that their cells can be
 *  revised), in the order they are fused: by anchor, then by tile. */
std::vector<std::pair<FallbackTileKey, RegionScan>> fallbackTileScans(
    const WorldScan& w, const ScanPoints& scan, const RegionPartition& partition, ScanOwners& owners,
    double fb_dist, double tile_m, const std::map<FallbackTileKey, std::unique_ptr<LocalDenseMap>>& tiles)
{
    std::vector<std::pair<FallbackTileKey, RegionScan>> out;
    const double shadow_margin = -1.0;
    std::set<long> anchors;
    for (const auto& kv : owners.fb_hits) anchors.insert(kv.first.anchor);
    const Eigen::Vector2d reach = Eigen::Vector2d::Constant(fb_dist + 2.0 * tile_m);
    for (const long id : partition.regionsInBox(w.lo - reach, w.hi + reach))
        if (tiles.lower_bound(firstTileOf(id)) != tiles.lower_bound(firstTileOf(id + 1)))
            anchors.insert(id);
    for (const long id : anchors)
    {
        const auto& to_current = owners.anchorMap(id);
        if (!to_current) continue;  // withheld or folded anchor: its tiles wait
        std::set<FallbackTileKey> keys;
        for (auto it = tiles.lower_bound(firstTileOf(id)); it != tiles.end() && it->first.anchor == id; ++it)
            keys.insert(it->first);
        for (auto it = owners.fb_hits.lower_bound(firstTileOf(id));
             it != owners.fb_hits.end() && it->first.anchor == id; ++it)
            keys.insert(it->first);
        for (const FallbackTileKey& key : keys)
        {
            Candidate c{id, fallbackTileTriangle(key, tile_m), *to_current, {}, {}, false};
            Vertices cur;
            for (size_t v = 0; v < 3; ++v) cur[v] = c.to_current.mapPoint(c.reference[v]);
            c.lo = cur[0].cwiseMin(cur[1]).cwiseMin(cur[2]);
            c.hi = cur[0].cwiseMax(cur[1]).cwiseMax(cur[2]);
            if (!boxesOverlap(c.lo, c.hi, w.lo, w.hi)) continue;
            RegionScan rs;
            if (const auto h = owners.fb_hits.find(key); h != owners.fb_hits.end()) rs = std::move(h->second);
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
            out.emplace_back(key, std::move(rs));
        }
    }
    return out;
}
}  // namespace

HybridMetricMap::InsertStats HybridMetricMap::insertScan(
    const ScanPoints& scan, const mrpt::math::TPose2D& vehicle_pose, const RegionPartition& partition,
    const RegionFilter& accept)
{
    core::TimedSection tle(profiler_, "dense.insertScan");
    scan.validate();  // values / noise: bad input is rejected before anything changes
    InsertStats st;
    const WorldScan w = scan.toWorld(vehicle_pose, options_.max_range_m, options_.no_return_free_range_m);
    st.beams = w.beams.size();
    st.beyond_range = w.beyond_range;
    st.no_return = w.no_return;

    // 1. Regions near the scan, with their reference -> current maps.
    ScanOwners owners(partition, accept, fallback_, options_.fallback_frame);
    {
        core::TimedSection t1(profiler_, "dense.insertScan.1_regions");
        owners.collectRegions(w, st);
    }
    // 2. Owner of each return (a region, a fallback tile, or none).
    const double fb_dist = options_.fallback_max_distance_m;
    {
        core::TimedSection t2(profiler_, "dense.insertScan.2_assign");
        owners.assignReturns(w, scan, options_, st);
    }

    // 3. Split the beams among the regions and fuse into every layer (Sec. 4.5).
    {
        core::TimedSection t3(profiler_, "dense.insertScan.3_clip_fuse");
        last_scan_regions_.clear();
        for (const size_t k : clipToRegions(w, scan, owners, shadowMargin(options_)))
        {
            const Candidate& c = owners.cands[k];
            localMapFor(c.id, c.reference).insert(owners.per_region[k]);
            last_scan_regions_.insert(c.id);
            ++st.regions_updated;
        }
    }

    // 3b. Fallback tiles near the scan: the new returns, and the free space of every beam
    // crossing a tile.
    if (fb_dist > 0)
    {
        core::TimedSection t3b(profiler_, "dense.insertScan.3b_fallback");
        for (auto& [key, rs] : fallbackTileScans(w, scan, partition, owners, fb_dist, options_.fallback_tile_m, fallback_))
            fallbackMapFor(key).insert(rs);
    }

    // 4. Background coarsening of idle, almost-empty regions (Sec. 4.1.3), if due.
    ++scans_;
    if (options_.coarsen_every_n_scans > 0 && scans_ % static_cast<size_t>(options_.coarsen_every_n_scans) == 0)
    {
        core::TimedSection t4(profiler_, "dense.insertScan.4_coarsen");
        st.regions_coarsened = coarsenIdleRegions().coarsened.size();
    }
    return st;
}

}  // namespace hymm::dense
