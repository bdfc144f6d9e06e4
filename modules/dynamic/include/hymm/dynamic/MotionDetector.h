/**
 * @file MotionDetector.h
 * @brief Slow- and fast-motion layers by local map differencing (thesis Sec. 6.3).
 *
 * Dynamic objects are found by differencing occupancy maps taken at different times
 * (Sec. 6.3, after ROMA [4]). In DenseSLAM the map is split into regions whose dense
 * content lives in the coordinates of each region's reference triangle, so maps taken
 * at different times are differenced region by region, cell by cell, without any
 * registration of two global maps of different uncertainty (Sec. 6.3.1).
 *
 * Per region this class keeps two motion layers, "slow" and "fast" (MotionLayer):
 * binary grids on the geometry of the region's occupancy grid, in reference-triangle
 * coordinates, so they move with the landmarks like every other layer (Sec. 6.3.2).
 *
 * One differencing of a region (differenceOccupancy):
 *   D = |P_now - P_then|                   per cell, P = P(occupied) of the occupancy layer
 *   D = 0 where an edge moved by at most shift_tolerance_cells (optional, not in the
 *         thesis): a cell that became occupied within that distance of an occupied cell
 *         of the earlier snapshot, or was vacated within it of one of the later snapshot
 *   D' = G_sigma * D                       Gaussian low-pass (optional; Fig. 6.9 d)
 *   M = D' > threshold                     (thesis: 0.5)
 *   M without its 8-connected clusters of fewer than min_cluster_cells cells
 *   layer |= M
 * The absolute difference is filtered (a moved object leaves +1 and -1 side by side,
 * which a signed low-pass would cancel). A cell first observed between the two
 * snapshots moves from the prior 0.5 by at most 0.5, so with threshold 0.5 newly seen
 * space is never "motion"; only cells that went from free to occupied or back are.
 * The low-pass removes the one-cell-wide flicker of static contours (range noise moves
 * a wall's return between neighbouring cells) while a moving object's swept area is
 * wider than the kernel.
 *
 * Fast motion (Sec. 6.3.2): every fast_period_s, only the regions under the sensor's
 * view (the caller passes them: HybridMetricMap::InsertStats or
 * RegionPartition::regionsInBox of the scan) are differenced against their own
 * snapshot fast_period_s earlier. Cost per call: O(cells of the regions in view).
 *
 * Slow motion (Sec. 6.3.1): every slow_period_s each region is differenced against its
 * snapshot slow_period_s earlier. A region's first reference snapshot is taken when it
 * first leaves the sensor's view (so it holds a whole pass, not the few scans of its
 * creation); from then on it is due every slow_period_s. Due regions wait in a queue
 * ordered by due time and at most slow_max_regions_per_call are processed per call,
 * so the slow work is amortised over calls and does not grow with map size per call.
 *
 * Fallback tiles (HybridMetricMap's fallback, dense/FallbackTiles.h: returns that no
 * region holds, kept in the frame of the nearest region) are differenced the same way,
 * each in its anchor's reference frame, so their marks move with the anchor's landmarks
 * too. Without them an object beyond every landmark triangle (a car parked off the road,
 * past the outer row of landmarks) cannot be marked by any layer.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include "hymm/dynamic/MotionLayer.h"

#include <hymm/dense/HybridMetricMap.h>
#include <hymm/ltr/RegionPartition.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <queue>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace hymm::dynamic
{
/** The two motion layers (Sec. 6.3.3). */
enum class MotionKind
{
    Slow,
    Fast
};
/** "slow" / "fast": layer names in metrics keys and figure names. */
const char* motionKindName(MotionKind k);

/** Result of one differencing (differenceOccupancy); images row-major, nx * ny. */
struct Difference
{
    int nx = 0, ny = 0;
    std::vector<float> raw;       //!< |P_now - P_then| (0 outside the triangle and at moved edges)
    std::vector<float> filtered;  //!< after the low-pass (== raw without it)
    std::vector<std::uint8_t> mask;  //!< filtered > threshold, small clusters removed
    /** Reused by the cluster filter (not state): a label per cell, cells per label. */
    std::vector<int> cluster_labels, cluster_sizes;
    /** Reused by the shift tolerance (not state): occupied cells of each snapshot,
     *  dilated by the tolerance. */
    std::vector<std::uint8_t> near_then, near_now;
    size_t marked() const;
};

/** One per-region occupancy snapshot: P(occupied) of every cell, the grid geometry
 *  and which cells belong to the region (updatable). */
struct OccupancySnapshot
{
    double t = 0;
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();
    double cell_size = 0;
    int nx = 0, ny = 0;
    std::vector<float> p;
    std::vector<std::uint8_t> inside;

    static OccupancySnapshot take(const dense::OccupancyLayer& occ, double t);
    /** take(), into this snapshot's storage (no allocation once it has the size). */
    void assign(const dense::OccupancyLayer& occ, double t);
    bool sameGeometry(const OccupancySnapshot& o) const;
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);
};

/** D, G * D and the threshold mask between two snapshots of the same geometry
 *  (throws std::invalid_argument otherwise). `sigma_cells` <= 0: no low-pass;
 *  `min_cluster_cells` <= 1: every cell above the threshold is kept. */
Difference differenceOccupancy(
    const OccupancySnapshot& then, const OccupancySnapshot& now, double sigma_cells,
    double threshold, int min_cluster_cells = 1, int shift_tolerance_cells = 0);
/** The same, into `out`'s storage (no allocation once it has the size). */
void differenceOccupancy(const OccupancySnapshot& then, const OccupancySnapshot& now,
                         double sigma_cells, double threshold, Difference& out,
                         int min_cluster_cells = 1, int shift_tolerance_cells = 0);
/** Sets d.raw to 0 where the change is explained by an edge that moved by at most
 *  `cells` (Chebyshev distance): became occupied (P > 0.5) near an occupied cell of
 *  `then`, or became free near an occupied cell of `now`. */
void suppressEdgeShifts(const OccupancySnapshot& then, const OccupancySnapshot& now, int cells, Difference& d);
/** Clears the 8-connected clusters of `d.mask` with fewer than `min_cells` cells. */
void removeSmallClusters(Difference& d, int min_cells);

class MotionDetector
{
public:
    /** Ini section [MotionDetector]; unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        bool enable_fast = true;          //!< fast-motion layer (Sec. 6.3.2)
        bool enable_slow = true;          //!< slow-motion layer (Sec. 6.3.1)
        double fast_period_s = 1.0;       //!< [s] thesis: 1 s
        double slow_period_s = 150.0;     //!< [s] thesis: 150 s
        double threshold = 0.5;           //!< on the filtered |dP| (thesis: 0.5)
        bool lowpass = true;              //!< Gaussian low-pass before the threshold
        double lowpass_sigma_m = 0.1;     //!< [m] its standard deviation
        /** Marked cells in 8-connected clusters smaller than these are dropped (1 = keep
         *  all, the thesis). Over the 150 s of a slow differencing a cell of a static
         *  outline flips alone now and then (pose and laser noise at 0.2 m cells) and the
         *  0.1 m low-pass does not smooth one cell below the threshold; a moved object
         *  changes a run of cells along its outline (docs/results.md, "False flags"). */
        int slow_min_cluster_cells = 2;
        int fast_min_cluster_cells = 1;
        /** A change within this many cells of an occupied cell of the other snapshot is
         *  taken for an edge that moved, not for motion (0 = off, the thesis). Over 150 s
         *  the returns of a static outline move by a cell with the pose and laser noise;
         *  a removed or added object has no occupied cell near it in the other snapshot
         *  (docs/results.md, "Edges that moved"). */
        int slow_shift_tolerance_cells = 1;
        int fast_shift_tolerance_cells = 0;
        /** The slow layer's tolerance in the fallback tiles: a tile's frame extrapolates its
         *  anchor's map (affine or rigid) up to tens of metres beyond the triangle, so a static wall
         *  seen there moves by a few cells over a slow period (seeds 1-20 of the slow
         *  scene: 1 / 2 / 3 cells give precision 0.81 / 0.86 / 0.89 at the same recall;
         *  docs/results.md, "Motion layers in the fallback tiles"). */
        int slow_tile_shift_tolerance_cells = 3;
        /** Slow differencings per call at most (the rest wait for the next calls). */
        int slow_max_regions_per_call = 4;
        /** Difference the fallback tiles too, where the map keeps returns no region holds
         *  ([HybridMetricMap] fallback_max_distance_m > 0). */
        bool fallback_tiles = true;
        /** Read a tile's marks inside regions too (OR with the regions' layers). Off:
         *  where a region holds a place its own layers judge it, as the dense map keeps a
         *  return in a tile only where no region holds it; on: more of the changes the
         *  regions miss are found, with more marks beside static outlines
         *  (docs/results.md, "Motion layers in the fallback tiles"). */
        bool tile_marks_inside_regions = false;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "MotionDetector") const;
    };

    /** What one step() did. */
    struct StepReport
    {
        size_t fast_differenced = 0;   //!< regions differenced for fast motion
        size_t slow_differenced = 0;   //!< regions differenced for slow motion
        size_t fast_cells_marked = 0;  //!< cells above threshold (before the OR)
        size_t slow_cells_marked = 0;
        size_t geometry_resets = 0;    //!< snapshots retaken after a coarsening
        size_t slow_pending = 0;       //!< slow entries still due after this call
    };

    /** Throws std::invalid_argument on invalid options. */
    explicit MotionDetector(const Options& options);

    const Options& options() const { return options_; }

    /** Runs the due differencings at time `t` [s]. `regions_in_view` are the regions
     *  the current scan covers (any order, duplicates allowed). Reads only. */
    StepReport step(const dense::HybridMetricMap& map, const std::vector<long>& regions_in_view,
                    double t);
    /** The same with the fallback tiles in view (HybridMetricMap::fallbackTilesInBox):
     *  each tile is differenced like a region (the counts of StepReport include them). */
    StepReport step(const dense::HybridMetricMap& map, const std::vector<long>& regions_in_view,
                    const std::vector<dense::FallbackTileKey>& tiles_in_view, double t);

    /** Drops the layers and snapshots of the regions `region_ids` (those the partition
     *  just removed; unknown ids are ignored) and of the fallback tiles anchored on them. O(removed * regions in view): the pipeline
     *  calls it every step, so it must not walk the map. Their due-queue entries are
     *  skipped when they come due. */
    void removeRegions(const std::vector<long>& region_ids);
    /** Drops the layers and snapshots of regions `map` no longer holds, found by walking
     *  every region held (O(regions)); for callers that do not know the removed ids. */
    void removeStaleRegions(const dense::HybridMetricMap& map);

    /** The layer of a region, or nullptr. */
    const MotionLayer* layer(MotionKind kind, long region_id) const;
    /** The layer of a fallback tile, or nullptr. */
    const MotionLayer* layer(MotionKind kind, const dense::FallbackTileKey& tile) const;
    /** Regions and fallback tiles holding motion state. */
    size_t size() const { return regions_.size(); }
    /** Fallback tiles holding motion state. */
    size_t tiles() const { return tile_ids_.size(); }
    /** Current triangles of the fallback tiles with a marked cell whose anchor is one
     *  of `anchors`: isDynamic() is false at every point outside the regions with
     *  hasMarks() and these triangles. */
    std::vector<ltr::TriangleFrame::Vertices> markedTileTriangles(
        const ltr::RegionPartition& partition, const std::vector<long>& anchors) const;
    /** [m] the margin a search for marked tiles near a point adds to its box
     *  (HybridMetricMap::fallbackReach, from the map at step(); 0 before). */
    double tileReach() const { return tile_reach_m_; }
    /** Cells set in the layers of `kind`, summed over regions. */
    size_t markedCells(MotionKind kind) const;
    /** True if a layer of region `region_id` has a marked cell: isDynamic() is false at
     *  every point outside the regions for which this holds. */
    bool hasMarks(long region_id) const;

    /** True if the global point `p` lies in a cell marked in the layer of `kind` of a
     *  region whose CURRENT triangle contains it, or of a fallback tile holding it: at a
     *  point in no region, or anywhere with Options::tile_marks_inside_regions. */
    bool isDynamic(MotionKind kind, const ltr::RegionPartition& partition,
                   const Eigen::Vector2d& p) const;
    /** Either layer. */
    bool isDynamic(const ltr::RegionPartition& partition, const Eigen::Vector2d& p) const;

    /** Draws the layer of `kind` into `out` (sized by the caller): cells whose centre
     *  lies in a current triangle (region, or fallback tile as isDynamic reads them) with
     *  a marked local cell get 1, others untouched. */
    void renderInto(MotionKind kind, const ltr::RegionPartition& partition,
                    mrpt::maps::COccupancyGridMap2D& out) const;
    /** HybridMetricMap::renderOccupancy, then every cell marked in either motion layer
     *  set back to the prior 0.5: the static occupancy map (Sec. 6.3). */
    void renderStaticOccupancy(const dense::HybridMetricMap& map,
                               const ltr::RegionPartition& partition, double resolution_m,
                               mrpt::maps::COccupancyGridMap2D& out) const;

    /** The last differencing of each kind with any cell marked (for figures as
     *  Fig. 6.9 c-d): region id, the snapshots' time span, and the images. */
    struct LastDifference
    {
        long region = -1;  //!< region id, or a fallback tile's internal id (>= 2^60); -1: none
        double t_then = 0, t_now = 0;
        Difference diff;
    };
    const LastDifference& lastDifference(MotionKind kind) const
    {
        return kind == MotionKind::Slow ? last_slow_ : last_fast_;
    }

    /** Layers, snapshots, schedule and last differences bit for bit, for a saved run
     *  (hymm-slam --save-state / --resume). The options are the config's, not saved. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

private:
    struct RegionState
    {
        MotionLayer slow, fast;
        std::optional<OccupancySnapshot> fast_ref, slow_ref;
        bool seen = false;  //!< in view at some call
        std::uint64_t view_call = 0;  //!< the last call (calls_) that had it in view
    };

    /** Fallback tiles share the regions' state, schedule and code under ids from
     *  kFirstTileId up; region ids stay far below it. */
    static constexpr long kFirstTileId = 1L << 60;
    static bool isTile(long id) { return id >= kFirstTileId; }
    /** The id of tile `key`, made on first use. */
    long tileId(const dense::FallbackTileKey& key);
    /** The occupancy layer of region or tile `id` in `map`, or nullptr. */
    const dense::OccupancyLayer* occupancyOf(const dense::HybridMetricMap& map, long id) const;
    /** Current triangle and reference -> current map of region or tile `id`; nullopt if
     *  the partition lacks it (or its anchor) or its current triangle is degenerate. */
    std::optional<std::pair<ltr::TriangleFrame::Vertices, ltr::AffineRegionMap>> frameOf(
        long id, const ltr::RegionPartition& partition) const;
    /** Drops the state of region or tile `id` (and its place in the view list). */
    void eraseUnit(long id);
    /** isDynamic() over the fallback tiles with a marked cell near `p`. */
    bool tileMarked(const ltr::RegionPartition& partition, const Eigen::Vector2d& p, bool slow,
                    bool fast) const;
    /** The tiles' part of saveState / loadState (ids, next id, geometry; checked). */
    void saveTiles(mrpt::serialization::CArchive& out) const;
    void loadTiles(mrpt::serialization::CArchive& in);
    /** Keeps marked_tile_anchors_ up to date after tile `id` gained marks or is erased. */
    void noteTileMarks(long id, bool had_marks, bool has_marks);

    /** Differences `st`'s snapshot against the region's occupancy now; ORs into
     *  `layer`, replaces the snapshot. Returns cells marked. */
    size_t differenceRegion(long id, const dense::OccupancyLayer& occ,
                            std::optional<OccupancySnapshot>& ref, MotionLayer& layer, double t,
                            LastDifference& last, StepReport& rep, int min_cluster_cells,
                            int shift_tolerance_cells);
    /** The storage of a removed region's snapshot, for the next region's first one: a
     *  region that comes into view after another was removed allocates nothing. */
    OccupancySnapshot spareSnapshot();
    void keepSpare(RegionState& st);
    static constexpr size_t kMaxSpare = 16;
    /** The slow layer's part of step(): first references of the regions that left the
     *  view (in view at the previous call, not at call `call`), then the due regions. */
    void stepSlow(const dense::HybridMetricMap& map, std::uint64_t call, double t, StepReport& rep);
    /** Sets every cell of `out` whose centre lies on a cell marked in a layer of
     *  `kinds` to `value`. */
    void paint(const std::vector<MotionKind>& kinds, const ltr::RegionPartition& partition,
               mrpt::maps::COccupancyGridMap2D& out, float value) const;
    double sigmaCells(double cell_size) const;

    const Options options_;
    /** Hashed: a step looks up each region in view in O(1), not through log2(N) nodes
     *  scattered over a heap that grows with the map; saveState() sorts the ids. */
    std::unordered_map<long, RegionState> regions_;
    std::vector<long> in_view_;  //!< regions in view at the previous call, sorted
    std::uint64_t calls_ = 0;    //!< step() calls (marks RegionState::view_call)
    /** Reused storage of differenceRegion. Allocating a snapshot and a difference per
     *  differencing (and a set node per region in view) made the time per call grow
     *  with the map at a fixed view: the allocator gets slower as the heap holds the
     *  state of more regions (docs/benchmarks.md, motion layers). */
    OccupancySnapshot scratch_now_;
    Difference scratch_diff_;
    std::vector<OccupancySnapshot> spare_;  //!< at most kMaxSpare
    /** (due time, region id), earliest first. */
    std::priority_queue<std::pair<double, long>, std::vector<std::pair<double, long>>,
                        std::greater<>>
        slow_due_;
    LastDifference last_slow_, last_fast_;
    /** Fallback tiles with state: key -> id (ordered by anchor, so an anchor's tiles are
     *  one range) and back. */
    std::map<dense::FallbackTileKey, long> tile_ids_;
    std::unordered_map<long, dense::FallbackTileKey> tile_keys_;
    long next_tile_id_ = kFirstTileId;
    /** Anchors -> how many of their tiles hold a marked cell (isDynamic looks only there). */
    std::unordered_map<long, int> marked_tile_anchors_;
    double tile_m_ = 0;       //!< [m] the map's fallback_tile_m, from step()
    dense::FallbackFrame tile_frame_ = dense::FallbackFrame::Affine;  //!< the map's fallback_frame, from step()
    double tile_reach_m_ = 0;  //!< [m] see tileReach()
};

}  // namespace hymm::dynamic
