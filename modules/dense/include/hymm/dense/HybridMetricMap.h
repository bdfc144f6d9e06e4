/**
 * @file HybridMetricMap.h
 * @brief Dense layers of every LTR: the dense half of HYMM (thesis Sec. 3.1-3.4, 4.1, 4.5).
 *
 * The feature map (EKF) estimates landmarks; hymm::ltr::RegionPartition triangulates
 * them into LTRs. This class keeps one LocalDenseMap per region, keyed by region id,
 * and fuses laser scans into them:
 *  1. each return is assigned to the region whose CURRENT triangle contains it
 *     (partition.findRegion), converted to that region's reference frame with the
 *     inverse of referenceToCurrent, and stored there; stored content never changes
 *     afterwards (local coordinates are invariant after fusion, Sec. 3.6);
 *  2. each beam (sensor -> return) is split into the regions it crosses: clipped to
 *     each triangle, mapped to that region's reference frame (an affine map keeps the
 *     segment straight) and used to update free cells there; beams with no return are
 *     free segments up to `no_return_free_range_m` (0 = none, ScanPoints.h says why);
 *     with a particle layer, each region also gets the returns it lies hidden behind
 *     (RegionScan::shadow_returns) for the particle free-space protection;
 *  3. returns in no region are counted and handed back (the pipeline's delayed-
 *     initialisation store takes them once a region covers them).
 * Only regions whose bounding box meets the scan's bounding box are visited
 * (partition.regionsInBox, a grid lookup), so the per-scan cost depends on the area the
 * scan covers, not on the number of regions or landmarks.
 *
 * Rendering evaluates every stored item at the CURRENT landmark estimates, so after a
 * loop closure the global dense map follows the corrected landmarks (Example 3.2).
 *
 * Layers (thesis Sec. 4.5 multi-layer maps), each enabled by an option and built per
 * region by makeLayer(): PointsLayer "points", OccupancyLayer "occupancy",
 * ParticlesLayer "particles", SogLayer "sog", PropertyLayer "property".
 *
 * Background coarsening (Sec. 4.1.3, Fig. 4.6): coarsenIdleRegions() re-samples the
 * occupancy grids of almost-empty regions that the last scan did not touch; with
 * coarsen_every_n_scans > 0 insertScan() calls it itself every n scans.
 *
 * Per-scan use by the pipeline (after the EKF update of that step):
 *   partition.update(view, t);            // or updateVertexPositions(view): current vertices
 *   dense.insertScan(ScanPoints::fromRangeScan(obs), vehicle_pose_estimate, partition);
 * and after regions are removed from the partition: dense.removeRegions(removed_ids) (or
 * dense.removeStaleRegions(partition), which finds them by walking the whole map).
 */
#pragma once

#include <hymm/core/TimeLogger.h>
#include <hymm/core/OptionTable.h>
#include "hymm/dense/FallbackTiles.h"
#include "hymm/dense/LocalDenseMap.h"
#include "hymm/dense/OccupancyLayer.h"
#include "hymm/dense/ParticlesLayer.h"
#include "hymm/dense/PointsLayer.h"
#include "hymm/dense/PropertyLayer.h"
#include "hymm/dense/ScalarField.h"
#include "hymm/dense/ScanPoints.h"
#include "hymm/dense/SogLayer.h"
#include "hymm/ltr/RegionPartition.h"

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPoint2DPDFGaussian.h>

#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace mrpt::serialization
{
class CArchive;
}

namespace hymm::dense
{
class HybridMetricMap
{
public:
    /** Ini section [HybridMetricMap]; the layers read [OccupancyLayer], [PointsLayer],
     *  [ParticlesLayer], [SogLayer] and [PropertyLayer] (loadAll reads all six).
     *  Unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        bool enable_points = true;     //!< keep raw returns (Sec. 3.9)
        bool enable_occupancy = true;  //!< keep occupancy grids (Sec. 4.1)
        bool enable_particles = false; //!< keep particle sets (Sec. 4.2)
        bool enable_sog = false;       //!< keep sums of Gaussians (Sec. 4.3)
        bool enable_property = false;  //!< keep scalar property grids (ScanPoints::values)
        double max_range_m = 25.0;     //!< [m] returns beyond are free space only (Table 4.1)
        /** [m] beams with no return (ScanPoints::no_return_bearings) are free space up
         *  to min(this, max_range_m); 0 = they give none (default). A beam with no echo
         *  is evidence of free space only up to some range: dark, specular or steeply
         *  inclined surfaces also return nothing, and the farther they are the weaker
         *  an echo they need to send back; so set it well below the sensor's reach. */
        double no_return_free_range_m = 0.0;
        /** insertScan() runs coarsenIdleRegions() every n scans; 0 = only when called.
         *  Needs [OccupancyLayer] coarse_cell_size_m > 0 to have an effect. */
        int coarsen_every_n_scans = 0;
        /** [m] fallback (FallbackTiles.h): a return in no region is kept in the frame of
         *  the nearest region whose current triangle is at most this far (the affine map
         *  of that region extrapolated beyond its triangle); 0 = off (returns in no region
         *  are only reported in InsertStats::unassigned). */
        double fallback_max_distance_m = 0.0;
        double fallback_tile_m = 10.0;  //!< [m] side of the fallback tiles (two triangles each)
        /** [m] a return goes to an existing fallback tile holding it whose anchor is at
         *  most this much farther than the nearest region (fallbackPlace(),
         *  FallbackTiles.h): fewer overlapping tiles to ray-cast per scan; 0 = always the
         *  nearest region's tile. */
        double fallback_reuse_m = 0.0;
        /** How fallback content follows its anchor (FallbackFrame): the affine map or its
         *  rigid part. */
        FallbackFrame fallback_frame = FallbackFrame::Affine;
        bool enable_profiler = false;  //!< CTimeLogger "dense.*" sections
        OccupancyLayer::Options occupancy;
        PointsLayer::Options points;
        ParticlesLayer::Options particles;
        SogLayer::Options sog;
        PropertyLayer::Options property;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        /** Reads only the [section] keys of this class. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        /** Reads [HybridMetricMap] and the five layer sections. */
        void loadAll(const mrpt::config::CConfigFileBase& cfg);
        void saveAll(mrpt::config::CConfigFileBase& cfg) const;
        void validate(const std::string& section = "HybridMetricMap") const;
    };

    /** Outcome of one insertScan(). */
    struct InsertStats
    {
        size_t beams = 0;             //!< beams considered (returns, then no-return beams)
        size_t returns_stored = 0;    //!< returns assigned to a region
        size_t returns_outside = 0;   //!< returns in no region (see `unassigned`)
        size_t beyond_range = 0;      //!< returns farther than max_range_m (free space only)
        size_t no_return = 0;         //!< no-return beams used as free space (no_return_free_range_m)
        size_t regions_visited = 0;   //!< regions whose bounding box meets the scan's
        size_t regions_updated = 0;   //!< regions that received rays or returns
        size_t regions_degenerate = 0;  //!< skipped: current triangle no longer a valid frame
        std::vector<Eigen::Vector2d> unassigned;  //!< global positions of returns in no region
        /** Parallel to `unassigned`: index of the return in ScanPoints::points (its raw
         *  measurement is ScanPoints::rangeBearing(index), what the delayed store keeps). */
        std::vector<size_t> unassigned_source;
        /** Parallel to `unassigned`: 1 if the fallback kept the return (in the frame of
         *  the nearest region), 0 if it is in no dense layer. */
        std::vector<char> unassigned_kept;
        size_t returns_fallback = 0;   //!< of returns_outside, kept by the fallback
        size_t regions_coarsened = 0;  //!< by the periodic coarsenIdleRegions() (if due)
        size_t regions_withheld = 0;   //!< regions the `accept` filter of insertScan() refused
        size_t returns_withheld = 0;   //!< returns owned by a refused region (see `withheld`)
        std::vector<Eigen::Vector2d> withheld;  //!< global positions of those returns
        /** Parallel to `withheld`: 1 if the fallback kept the return in the frame of the
         *  nearest region the filter accepts (never the refused owner). */
        std::vector<char> withheld_kept;
        size_t withheld_fallback = 0;  //!< of returns_withheld, kept by the fallback
    };

    /** Which content a render reads: everything (regions and fallback tiles), the
     *  regions only, or the fallback tiles only (scored apart: their error includes the
     *  extrapolation of the anchor's affine map). */
    enum class Content
    {
        All,
        Regions,
        Fallback
    };

    /** Decides, per region id, whether a scan may be fused into it now (see insertScan). */
    using RegionFilter = std::function<bool(long region_id)>;

    /** Outcome of one coarsenIdleRegions(): memory of the occupancy layers before and
     *  after, per coarsened region. */
    struct CoarsenReport
    {
        struct Region
        {
            long id;
            size_t bytes_before;  //!< OccupancyLayer::memoryBytes() before
            size_t bytes_after;   //!< and after
        };
        size_t regions_checked = 0;  //!< idle regions with an occupancy layer not coarse yet
        std::vector<Region> coarsened;
        size_t bytesBefore() const;
        size_t bytesAfter() const;
    };

    /** Throws std::invalid_argument on invalid options. */
    explicit HybridMetricMap(const Options& options);
    HybridMetricMap(const HybridMetricMap&) = delete;
    HybridMetricMap& operator=(const HybridMetricMap&) = delete;

    const Options& options() const { return options_; }

    /** Fuses one scan taken at `vehicle_pose` (estimate at observation time) into the
     *  regions of `partition`, whose current vertices must be up to date
     *  (RegionPartition::updateVertexPositions after the filter update).
     *  `accept` (optional) refuses regions whose local frame is not known well enough
     *  relative to the vehicle at this moment (Sec. 3.6, 3.7.3): a refused region gets
     *  neither returns nor free space from this scan, so a vehicle pose that is wrong
     *  relative to its vertices cannot write wrong local coordinates that no later
     *  correction would move. Its returns are handed back in InsertStats::withheld. */
    InsertStats insertScan(
        const ScanPoints& scan, const mrpt::math::TPose2D& vehicle_pose,
        const hymm::ltr::RegionPartition& partition, const RegionFilter& accept = {});

    /** Coarsens (OccupancyLayer::coarsen) the grid of every region that the last
     *  insertScan() did not update (Sec. 4.1.3 background function). */
    CoarsenReport coarsenIdleRegions();

    /** Keeps one return `ret` (global, current estimate) seen from `sensor` in a fallback
     *  tile of the nearest region within fallback_max_distance_m whose current triangle
     *  is a frame (as insertScan's fallback does, without its free space: the beam is an
     *  old one, e.g. a return that waited in the delayed store while no region was near).
     *  `range_std_m` / `bearing_std_rad` model it in the SOG and particle layers. Returns
     *  false (nothing changes) with the fallback off or no such region. */
    bool insertFallbackReturn(
        const Eigen::Vector2d& sensor, const Eigen::Vector2d& ret, double range_std_m,
        double bearing_std_rad, const hymm::ltr::RegionPartition& partition);

    /** Fuses a scan piece already in the reference frame of `region_id` (e.g. returns
     *  kept by the delayed-initialisation store until the region existed) into every
     *  layer of that region. Throws std::out_of_range if the partition lacks the region. */
    void insertRegionScan(long region_id, const RegionScan& scan,
                          const hymm::ltr::RegionPartition& partition);

    /** Drops local maps of regions the partition no longer has; returns their ids.
     *  Walks every region and fallback tile (O(map)): when the caller knows which
     *  regions it removed, removeRegions() does the same in O(removed). */
    std::vector<long> removeStaleRegions(const hymm::ltr::RegionPartition& partition);
    /** Drops the local maps of `region_ids` and the fallback tiles anchored on them (the
     *  regions the partition just removed); ids without content are ignored. Returns the
     *  ids that had a local map. O(k log n) for k ids: the per-step cost does not grow
     *  with the map. */
    std::vector<long> removeRegions(const std::vector<long>& region_ids);

    // --- global rendering at the current landmark estimates ------------------------
    /** Every stored return, mapped through its region's reference -> current map. */
    void renderPoints(
        const hymm::ltr::RegionPartition& partition, mrpt::maps::CSimplePointsMap& out,
        Content content = Content::All) const;
    /** Occupancy at `resolution_m` over the bounding box of the current triangles that
     *  hold a grid; each cell centre reads the local cell of the region containing it
     *  (cells in no region stay at 0.5). */
    void renderOccupancy(
        const hymm::ltr::RegionPartition& partition, double resolution_m,
        mrpt::maps::COccupancyGridMap2D& out, Content content = Content::All) const;
    /** SOG surface (Fig. 4.12 b): sum of all peak-1 Gaussians at `resolution_m` over the
     *  bounding box of the current triangles holding a SOG layer plus `margin_m`. */
    void renderSogSurface(
        const hymm::ltr::RegionPartition& partition, double resolution_m, ScalarField& out,
        double margin_m = 1.0) const;
    /** 1-sigma ellipses of all Gaussians at the current region positions (Fig. 4.13). */
    std::vector<std::vector<Eigen::Vector2d>> renderSogEllipses(
        const hymm::ltr::RegionPartition& partition, int points = 36) const;
    /** Property mean and standard deviation at `resolution_m` over the bounding box of
     *  the current triangles holding a property layer; unobserved cells are NaN. */
    void renderProperty(
        const hymm::ltr::RegionPartition& partition, double resolution_m, ScalarField& mean,
        ScalarField& stddev) const;
    /** Any layer kind into a map the caller sized (see DenseLayer::renderInto). */
    void renderLayer(
        const std::string& kind, const hymm::ltr::RegionPartition& partition,
        mrpt::maps::CMetricMap& out, Content content = Content::All) const;
    /** Every Gaussian of the SOG layers at the current region positions (the means and
     *  covariances renderSogEllipses draws), as MRPT PDFs. */
    std::vector<mrpt::poses::CPoint2DPDFGaussian> renderSogGaussians(
        const hymm::ltr::RegionPartition& partition, Content content = Content::All) const;

    // --- access ------------------------------------------------------------------
    size_t size() const { return maps_.size(); }
    /** Fallback triangles holding content (FallbackTiles.h). */
    size_t fallbackTiles() const { return fallback_.size(); }
    /** The content of fallback triangle `key`, or nullptr. */
    const LocalDenseMap* fallbackMap(const FallbackTileKey& key) const;
    /** The map through which the fallback content of `anchor` is rendered (the
     *  region's reference -> current map or its rigid part, Options::fallback_frame), or
     *  nullopt when the region is gone or folded. */
    std::optional<hymm::ltr::AffineRegionMap> fallbackToCurrent(
        const hymm::ltr::RegionPartition& partition, long anchor) const
    {
        return usableReferenceToCurrent(partition, anchor, options_.fallback_frame);
    }
    /** Keys of every fallback triangle, ordered by anchor. */
    std::vector<FallbackTileKey> fallbackTileKeys() const;
    /** [m] how far from its anchor's current triangle a fallback triangle is looked for
     *  (fallbackTilesInBox and readers that search tiles near a point): the fallback
     *  distance plus a tile's diagonal, and a quarter more for the anchor's later
     *  deformation. A rule of thumb, not a bound: a tile whose anchor's triangle has
     *  stretched more is missed by those searches (the renders still draw it). */
    double fallbackReach() const;
    /** Keys of the fallback triangles whose current position (through the anchor's
     *  reference -> current map) meets the box [lo, hi], among those of the anchors
     *  within fallbackReach() of it. Only anchors the partition's lookup grid lists near
     *  the box are visited, so the cost depends on the content near the box, not on the
     *  map's size. */
    std::vector<FallbackTileKey> fallbackTilesInBox(
        const hymm::ltr::RegionPartition& partition, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) const;
    /** nullptr if the region has no dense content yet. */
    const LocalDenseMap* localMap(long region_id) const;
    std::vector<long> regionIds() const;
    size_t memoryBytes() const;
    /** memoryBytes() of all layers of each kind, summed over regions. */
    std::map<std::string, size_t> memoryBytesByKind() const;
    /** DenseLayer::size() of all layers of each kind, summed over regions (points,
     *  occupancy cells ever updated, particles, Gaussians, property cells). */
    std::map<std::string, size_t> sizeByKind() const;

    /** State of one region's occupancy layer (Sec. 4.1.3 per-region resolution). */
    struct OccupancyRegionStats
    {
        long id = 0;
        bool coarse = false;       //!< OccupancyLayer::isCoarse()
        double cell_size_m = 0;    //!< current local cell size
        size_t cells = 0;          //!< cells meeting the triangle (updatable)
        size_t occupied = 0;       //!< of those, P(occupied) > occupied_prob
        size_t free = 0;           //!< of those, P(occupied) < [OccupancyLayer] coarsen_min_prob
        size_t memory_bytes = 0;   //!< OccupancyLayer::memoryBytes()
    };
    /** One entry per region holding an occupancy layer, by region id. */
    std::vector<OccupancyRegionStats> occupancyRegionStats(double occupied_prob) const;
    /** Layer kinds this map builds, in construction order. */
    std::vector<std::string> enabledKinds() const;
    /** Empty layer of `kind` for a region (nullptr if the kind is unknown/disabled). */
    std::unique_ptr<DenseLayer> makeLayer(
        const std::string& kind, const hymm::ltr::TriangleFrame::Vertices& reference) const;
    mrpt::system::CTimeLogger& profiler() const { return profiler_.get(); }

    // --- persistence -------------------------------------------------------------
    void save(std::ostream& out) const;
    /** Replaces the content; throws std::runtime_error on malformed input. */
    void load(std::istream& in);
    /** Saved run state (hymm-slam --save-state): every member a later step reads, bit
     *  for bit; loadState() replaces them (options come from the config). Throws
     *  std::runtime_error on a corrupt or truncated state. Source: HybridMetricMapState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);
    /** The fallback tiles as text (map.hymm; save()/load() hold the regions only);
     *  loadFallbackTiles() replaces them and throws std::runtime_error on malformed
     *  input. Source: HybridMetricMapState.cpp. */
    void saveFallbackTiles(std::ostream& out) const;
    void loadFallbackTiles(std::istream& in);

private:
    LocalDenseMap& localMapFor(long region_id, const hymm::ltr::TriangleFrame::Vertices& reference);
    LocalDenseMap& fallbackMapFor(const FallbackTileKey& key);
    /** Calls fn(map, reference -> current) for the fallback tiles (first) and the regions
     *  (then, so that a region's own content is drawn over extrapolated content) that
     *  `content` selects, skipping degenerate current triangles. */
    void forEachMap(
        const hymm::ltr::RegionPartition& partition, Content content,
        const std::function<void(const LocalDenseMap&, const hymm::ltr::AffineRegionMap&)>& fn) const;
    /** Bounding box of the current triangles of regions holding a layer of `kind`;
     *  false if there is none. */
    bool layerBox(
        const std::string& kind, const hymm::ltr::RegionPartition& partition, Eigen::Vector2d& lo,
        Eigen::Vector2d& hi, Content content = Content::All) const;

    const Options options_;
    std::map<long, std::unique_ptr<LocalDenseMap>> maps_;
    /** Fallback triangles, ordered by anchor region (FallbackTiles.h); not saved by save(). */
    std::map<FallbackTileKey, std::unique_ptr<LocalDenseMap>> fallback_;
    std::set<long> last_scan_regions_;  //!< regions updated by the last insertScan()
    size_t scans_ = 0;                  //!< insertScan() calls
    core::LazyTimeLogger profiler_;
};

}  // namespace hymm::dense
