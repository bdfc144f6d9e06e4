#include "hymm/dense/HybridMetricMap.h"

#include "hymm/dense/geometry.h"

#include <algorithm>
#include <cmath>
#include <istream>
#include <limits>
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
    const hymm::ltr::Region* region;
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
    const Vertices& ref = c.region->reference;
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
        return std::make_unique<PointsLayer>(options_.points);
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
    }
    return *slot;
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
                Candidate c{id, &r, partition.referenceToCurrent(id), {}, {}, false};
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

    // 2. Owner of each return: one region (lowest id on shared borders).
    std::vector<RegionScan> per_region(cands.size());
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
                continue;
            }
            if (cands[it->second].withheld)
            {
                ++st.returns_withheld;
                st.withheld.push_back(b.end);
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
            localMapFor(cands[k].id, cands[k].region->reference).insert(rs);
            last_scan_regions_.insert(cands[k].id);
            ++st.regions_updated;
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
    return removed;
}

void HybridMetricMap::renderLayer(
    const std::string& kind, const RegionPartition& partition, mrpt::maps::CMetricMap& out) const
{
    mrpt::system::CTimeLoggerEntry tle(profiler_, "dense.render." + kind);
    for (const auto& [id, map] : maps_)
    {
        if (!partition.has(id)) continue;
        const DenseLayer* layer = map->layer(kind);
        if (!layer) continue;
        AffineRegionMap to_current;
        try
        {
            to_current = partition.referenceToCurrent(id);
        }
        catch (const std::invalid_argument&)
        {
            continue;  // degenerate current triangle: no valid position for its content
        }
        layer->renderInto(to_current, out);
    }
}

void HybridMetricMap::renderPoints(
    const RegionPartition& partition, mrpt::maps::CSimplePointsMap& out) const
{
    out.clear();
    renderLayer(PointsLayer::kKind, partition, out);
}

void HybridMetricMap::renderOccupancy(
    const RegionPartition& partition, double resolution_m, mrpt::maps::COccupancyGridMap2D& out) const
{
    if (!(resolution_m > 0))
        throw std::invalid_argument("HybridMetricMap::renderOccupancy: resolution must be > 0");
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d hi = -lo;
    for (const auto& [id, map] : maps_)
    {
        if (!partition.has(id) || !map->layer(OccupancyLayer::kKind)) continue;
        for (const auto& v : partition.region(id).current)
        {
            lo = lo.cwiseMin(v);
            hi = hi.cwiseMax(v);
        }
    }
    if (!(lo.x() <= hi.x())) lo = hi = Eigen::Vector2d::Zero();  // nothing to draw
    out.setSize(
        static_cast<float>(lo.x() - resolution_m), static_cast<float>(hi.x() + resolution_m),
        static_cast<float>(lo.y() - resolution_m), static_cast<float>(hi.y() + resolution_m),
        static_cast<float>(resolution_m), 0.5f);
    renderLayer(OccupancyLayer::kKind, partition, out);
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
    return n;
}

std::map<std::string, size_t> HybridMetricMap::memoryBytesByKind() const
{
    std::map<std::string, size_t> out;
    for (const auto& kv : maps_)
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
