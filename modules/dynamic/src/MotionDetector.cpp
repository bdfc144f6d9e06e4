#include "hymm/dynamic/MotionDetector.h"

#include <hymm/core/config_utils.h>
#include <hymm/dense/OccupancyLayer.h>
#include <hymm/dense/geometry.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hymm::dynamic
{
const char* motionKindName(MotionKind k) { return k == MotionKind::Slow ? "slow" : "fast"; }

hymm::core::OptionTable MotionDetector::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.flag("enable_fast", enable_fast, "fast-motion layer (Sec. 6.3.2)");
    t.flag("enable_slow", enable_slow, "slow-motion layer (Sec. 6.3.1)");
    t.real("fast_period_s", fast_period_s, "s", above(0, 1e6), "differencing period of the fast layer (thesis: 1 s)");
    t.real("slow_period_s", slow_period_s, "s", above(0, 1e6), "differencing period of the slow layer (thesis: 150 s)");
    t.real("threshold", threshold, "", openInterval(0, 1), "on the filtered |dP| (thesis: 0.5)");
    t.flag("lowpass", lowpass, "Gaussian low-pass before the threshold");
    t.real("lowpass_sigma_m", lowpass_sigma_m, "m", above(0, 100), "standard deviation of the low-pass");
    t.integer("slow_min_cluster_cells", slow_min_cluster_cells, "", 1, 1000000,
              "slow layer: marked cells in 8-connected clusters of fewer cells are dropped (1: keep all)");
    t.integer("fast_min_cluster_cells", fast_min_cluster_cells, "", 1, 1000000,
              "fast layer: the same (1: keep all)");
    t.integer("slow_shift_tolerance_cells", slow_shift_tolerance_cells, "", 0, 100,
              "slow layer: a change within this many cells of an occupied cell of the other snapshot is an edge that moved (0: off)");
    t.integer("fast_shift_tolerance_cells", fast_shift_tolerance_cells, "", 0, 100,
              "fast layer: the same (0: off)");
    t.integer("slow_tile_shift_tolerance_cells", slow_tile_shift_tolerance_cells, "", 0, 100,
              "slow layer of the fallback tiles: the same (their frames extrapolate the anchor's)");
    t.integer("slow_max_regions_per_call", slow_max_regions_per_call, "", 1, 1000000,
              "slow differencings per call at most (the rest wait for the next calls)");
    t.flag("fallback_tiles", fallback_tiles,
           "difference the fallback tiles too (returns no region holds; [HybridMetricMap] fallback_max_distance_m > 0)");
    t.flag("tile_marks_inside_regions", tile_marks_inside_regions,
           "read a tile's marks inside regions too (false: the regions' own layers judge their area)");
    return t;
}

void MotionDetector::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void MotionDetector::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void MotionDetector::Options::validate(const std::string& s) const
{
    auto bad = [&](const std::string& key, double v, const std::string& what) {
        throw std::invalid_argument("[" + s + "] " + key + "=" + std::to_string(v) + ": " + what);
    };
    if (!(fast_period_s > 0)) bad("fast_period_s", fast_period_s, "must be > 0");
    if (!(slow_period_s > 0)) bad("slow_period_s", slow_period_s, "must be > 0");
    if (!(threshold > 0 && threshold < 1)) bad("threshold", threshold, "must be in (0, 1)");
    if (!(lowpass_sigma_m > 0)) bad("lowpass_sigma_m", lowpass_sigma_m, "must be > 0");
    if (slow_max_regions_per_call < 1)
        bad("slow_max_regions_per_call", slow_max_regions_per_call, "must be >= 1");
}

MotionDetector::MotionDetector(const Options& options) : options_(options) { options_.validate(); }

double MotionDetector::sigmaCells(double cell_size) const
{
    return options_.lowpass ? options_.lowpass_sigma_m / cell_size : 0.0;
}

OccupancySnapshot MotionDetector::spareSnapshot()
{
    if (spare_.empty()) return {};
    OccupancySnapshot s = std::move(spare_.back());
    spare_.pop_back();
    return s;
}

void MotionDetector::keepSpare(RegionState& st)
{
    for (auto* ref : {&st.fast_ref, &st.slow_ref})
        if (*ref && spare_.size() < kMaxSpare) spare_.push_back(std::move(**ref));
}

size_t MotionDetector::differenceRegion(long id, const dense::OccupancyLayer& occ,
                                        std::optional<OccupancySnapshot>& ref, MotionLayer& layer,
                                        double t, LastDifference& last, StepReport& rep,
                                        int min_cluster_cells, int shift_tolerance_cells)
{
    // The snapshot and difference are built in reused storage and swapped in: no
    // allocation per differencing once the scratch buffers have the grid's size.
    OccupancySnapshot& now = scratch_now_;
    now.assign(occ, t);
    if (!ref || !ref->sameGeometry(now))
    {
        // The grid was coarsened (Sec. 4.1.3) since: restart from the new grid.
        if (ref) ++rep.geometry_resets;
        if (!ref) ref = spareSnapshot();
        std::swap(*ref, now);
        return 0;
    }
    Difference& d = scratch_diff_;
    differenceOccupancy(*ref, now, sigmaCells(now.cell_size), options_.threshold, d, min_cluster_cells,
                        shift_tolerance_cells);
    const size_t marked = d.marked();
    const bool had_marks = isTile(id) && hasMarks(id);
    layer.orMask(now.origin, now.cell_size, now.nx, now.ny, d.mask);
    if (isTile(id)) noteTileMarks(id, had_marks, hasMarks(id));
    if (marked > 0)
    {
        last.region = id;
        last.t_then = ref->t;
        last.t_now = t;
        std::swap(last.diff, d);
    }
    std::swap(*ref, now);
    return marked;
}

MotionDetector::StepReport MotionDetector::step(
    const dense::HybridMetricMap& map, const std::vector<long>& regions_in_view, double t)
{
    StepReport rep;
    // Regions in view this call: marked by the call number (a duplicate id finds its mark),
    // so no set of the view is built; the sorted list is kept for the next call.
    const std::uint64_t call = ++calls_;
    std::vector<long> view;
    view.reserve(regions_in_view.size());
    for (long id : regions_in_view)
    {
        const auto* occ = occupancyOf(map, id);
        if (!occ) continue;
        auto& st = regions_[id];
        if (st.view_call == call) continue;  // a duplicate
        st.view_call = call;
        view.push_back(id);
        st.seen = true;
        if (!options_.enable_fast) continue;
        // Sec. 6.3.2: only the regions under the sensor's view, every fast_period_s.
        if (!st.fast_ref)
        {
            st.fast_ref = spareSnapshot();
            st.fast_ref->assign(*occ, t);
        }
        else if (t - st.fast_ref->t >= options_.fast_period_s - 1e-9)
        {
            rep.fast_cells_marked += differenceRegion(id, *occ, st.fast_ref, st.fast, t, last_fast_, rep,
                                                      options_.fast_min_cluster_cells,
                                                      options_.fast_shift_tolerance_cells);
            ++rep.fast_differenced;
        }
    }
    if (options_.enable_slow) stepSlow(map, call, t, rep);
    std::sort(view.begin(), view.end());
    in_view_ = std::move(view);
    return rep;
}

void MotionDetector::stepSlow(const dense::HybridMetricMap& map, std::uint64_t call, double t,
                              StepReport& rep)
{
    // A region's first slow reference: when it leaves the view (a whole pass).
    for (long id : in_view_)
    {
        const auto it = regions_.find(id);
        if (it == regions_.end() || it->second.view_call == call) continue;  // gone, or in view
        const auto* occ = occupancyOf(map, id);
        if (!occ || it->second.slow_ref) continue;
        it->second.slow_ref = spareSnapshot();
        it->second.slow_ref->assign(*occ, t);
        slow_due_.emplace(t + options_.slow_period_s, id);
    }
    // Sec. 6.3.1: due regions, a bounded number per call (amortised).
    int done = 0;
    while (!slow_due_.empty() && slow_due_.top().first <= t + 1e-9 &&
           done < options_.slow_max_regions_per_call)
    {
        const long id = slow_due_.top().second;
        slow_due_.pop();
        const auto it = regions_.find(id);
        const auto* occ = occupancyOf(map, id);
        if (it == regions_.end() || !occ || !it->second.slow_ref) continue;  // region gone
        rep.slow_cells_marked +=
            differenceRegion(id, *occ, it->second.slow_ref, it->second.slow, t, last_slow_, rep,
                             options_.slow_min_cluster_cells,
                             isTile(id) ? options_.slow_tile_shift_tolerance_cells : options_.slow_shift_tolerance_cells);
        ++rep.slow_differenced;
        ++done;
        slow_due_.emplace(t + options_.slow_period_s, id);
    }
    rep.slow_pending = 0;
    // Counting the due entries left would walk the queue; the top tells whether any is.
    if (!slow_due_.empty() && slow_due_.top().first <= t + 1e-9) rep.slow_pending = 1;
}

void MotionDetector::eraseUnit(long id)
{
    if (const auto st = regions_.find(id); st != regions_.end())
    {
        if (isTile(id)) noteTileMarks(id, hasMarks(id), false);
        keepSpare(st->second);
        regions_.erase(st);
    }
    const auto it = std::lower_bound(in_view_.begin(), in_view_.end(), id);
    if (it != in_view_.end() && *it == id) in_view_.erase(it);
    tile_keys_.erase(id);
}

void MotionDetector::removeRegions(const std::vector<long>& region_ids)
{
    for (long id : region_ids)
    {
        eraseUnit(id);
        // A tile hangs off its anchor's frame and goes with it (HybridMetricMap drops it).
        const auto first = tile_ids_.lower_bound(dense::firstFallbackTileKey(id));
        auto last = first;
        for (; last != tile_ids_.end() && last->first.anchor == id; ++last) eraseUnit(last->second);
        tile_ids_.erase(first, last);
    }
    // Queue entries of removed regions and tiles are skipped when they come due.
}

void MotionDetector::removeStaleRegions(const dense::HybridMetricMap& map)
{
    std::vector<long> gone;
    for (const auto& kv : regions_)
    {
        const long id = kv.first;
        if (isTile(id) ? !map.fallbackMap(tile_keys_.at(id)) : !map.localMap(id)) gone.push_back(id);
    }
    for (const long id : gone)
    {
        if (isTile(id)) tile_ids_.erase(tile_keys_.at(id));
        eraseUnit(id);
    }
    // Queue entries of removed regions and tiles are skipped when they come due.
}

const MotionLayer* MotionDetector::layer(MotionKind kind, long region_id) const
{
    const auto it = regions_.find(region_id);
    if (it == regions_.end()) return nullptr;
    return kind == MotionKind::Slow ? &it->second.slow : &it->second.fast;
}

bool MotionDetector::hasMarks(long region_id) const
{
    const auto it = regions_.find(region_id);
    return it != regions_.end() && (it->second.slow.count() > 0 || it->second.fast.count() > 0);
}

size_t MotionDetector::markedCells(MotionKind kind) const
{
    size_t n = 0;
    for (const auto& [id, st] : regions_) n += (kind == MotionKind::Slow ? st.slow : st.fast).count();
    return n;
}

bool MotionDetector::isDynamic(MotionKind kind, const ltr::RegionPartition& partition,
                               const Eigen::Vector2d& p) const
{
    // A point a region holds reads the regions' layers; one in no region the tiles' (as
    // the dense map keeps a return in a tile only where no region holds it).
    const auto holders = partition.findRegions(p);
    if ((holders.empty() || options_.tile_marks_inside_regions) &&
        tileMarked(partition, p, kind == MotionKind::Slow, kind == MotionKind::Fast))
        return true;
    for (long id : holders)
    {
        const auto* l = layer(kind, id);
        if (!l || l->count() == 0) continue;
        try
        {
            if (l->at(partition.referenceToCurrent(id).inverseMapPoint(p))) return true;
        }
        catch (const std::exception&)
        {
            // A folded current triangle has no reference -> current map: nothing to read.
        }
    }
    return false;
}

bool MotionDetector::isDynamic(const ltr::RegionPartition& partition, const Eigen::Vector2d& p) const
{
    // isDynamic(Slow) || isDynamic(Fast), with one look-up of the regions holding p.
    const auto holders = partition.findRegions(p);
    if ((holders.empty() || options_.tile_marks_inside_regions) && tileMarked(partition, p, true, true))
        return true;
    for (long id : holders)
    {
        const auto it = regions_.find(id);
        if (it == regions_.end()) continue;
        const MotionLayer &slow = it->second.slow, &fast = it->second.fast;
        if (slow.count() == 0 && fast.count() == 0) continue;
        try
        {
            const Eigen::Vector2d r = partition.referenceToCurrent(id).inverseMapPoint(p);
            if ((slow.count() > 0 && slow.at(r)) || (fast.count() > 0 && fast.at(r))) return true;
        }
        catch (const std::exception&)
        {
            // A folded current triangle has no reference -> current map: nothing to read.
        }
    }
    return false;
}

void MotionDetector::paint(const std::vector<MotionKind>& kinds, const ltr::RegionPartition& partition,
                           mrpt::maps::COccupancyGridMap2D& out, float value) const
{
    for (const auto& [id, st] : regions_)
    {
        std::vector<const MotionLayer*> layers;
        for (auto k : kinds)
            if (const auto* l = layer(k, id); l && l->count() > 0) layers.push_back(l);
        if (layers.empty()) continue;
        const auto frame = frameOf(id, partition);
        if (!frame) continue;  // gone, or a folded triangle: not drawn
        const auto& [cur, ref_to_cur] = *frame;
        Eigen::Vector2d lo = cur[0], hi = cur[0];
        for (const auto& v : cur)
        {
            lo = lo.cwiseMin(v);
            hi = hi.cwiseMax(v);
        }
        const int x0 = std::max(0, out.x2idx(lo.x())), y0 = std::max(0, out.y2idx(lo.y()));
        const int x1 = std::min(static_cast<int>(out.getSizeX()) - 1, out.x2idx(hi.x()));
        const int y1 = std::min(static_cast<int>(out.getSizeY()) - 1, out.y2idx(hi.y()));
        for (int cy = y0; cy <= y1; ++cy)
            for (int cx = x0; cx <= x1; ++cx)
            {
                const Eigen::Vector2d c(out.idx2x(static_cast<size_t>(cx)), out.idx2y(static_cast<size_t>(cy)));
                if (!dense::triangleContains(cur, c, 1e-9)) continue;
                const Eigen::Vector2d r = ref_to_cur.inverseMapPoint(c);
                for (const auto* l : layers)
                    if (l->at(r))
                    {
                        // A tile's marks count only where no region holds the place (the
                        // regions' own layers judge it): tiles overlap regions and see
                        // the same walls through an extrapolated frame (isDynamic too).
                        if (!isTile(id) || options_.tile_marks_inside_regions || partition.findRegions(c).empty())
                            out.setCell(cx, cy, value);
                        break;
                    }
            }
    }
}

void MotionDetector::renderInto(MotionKind kind, const ltr::RegionPartition& partition,
                                mrpt::maps::COccupancyGridMap2D& out) const
{
    paint({kind}, partition, out, 1.0f);
}

void MotionDetector::renderStaticOccupancy(const dense::HybridMetricMap& map,
                                           const ltr::RegionPartition& partition, double resolution_m,
                                           mrpt::maps::COccupancyGridMap2D& out) const
{
    map.renderOccupancy(partition, resolution_m, out);
    paint({MotionKind::Slow, MotionKind::Fast}, partition, out, 0.5f);
}

}  // namespace hymm::dynamic
