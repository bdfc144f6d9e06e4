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
 *     segment straight) and used to update free cells there;
 *  3. returns in no region are counted and handed back (the pipeline's delayed-
 *     initialisation store takes them once a region covers them).
 * Only regions whose bounding box meets the scan's bounding box are visited
 * (partition.regionsInBox, a grid lookup), so the per-scan cost depends on the area the
 * scan covers, not on the number of regions or landmarks.
 *
 * Rendering evaluates every stored item at the CURRENT landmark estimates, so after a
 * loop closure the global dense map follows the corrected landmarks (Example 3.2).
 *
 * Per-scan use by the pipeline (after the EKF update of that step):
 *   partition.update(view, t);            // or updateVertexPositions(view): current vertices
 *   dense.insertScan(ScanPoints::fromRangeScan(obs), vehicle_pose_estimate, partition);
 * and after regions are removed from the partition: dense.removeStaleRegions(partition).
 */
#pragma once

#include "hymm/dense/LocalDenseMap.h"
#include "hymm/dense/OccupancyLayer.h"
#include "hymm/dense/PointsLayer.h"
#include "hymm/dense/ScanPoints.h"
#include "hymm/ltr/RegionPartition.h"

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/system/CTimeLogger.h>

#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace hymm::dense
{
class HybridMetricMap
{
public:
    /** Ini section [HybridMetricMap]; the layers read [OccupancyLayer] and [PointsLayer]
     *  (loadAll reads the three). Unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        bool enable_points = true;     //!< keep raw returns (Sec. 3.9)
        bool enable_occupancy = true;  //!< keep occupancy grids (Sec. 4.1)
        double max_range_m = 25.0;     //!< [m] returns beyond are free space only (Table 4.1)
        bool enable_profiler = false;  //!< CTimeLogger "dense.*" sections
        OccupancyLayer::Options occupancy;
        PointsLayer::Options points;

        /** Reads only the [section] keys of this class. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        /** Reads [HybridMetricMap], [OccupancyLayer] and [PointsLayer]. */
        void loadAll(const mrpt::config::CConfigFileBase& cfg);
        void saveAll(mrpt::config::CConfigFileBase& cfg) const;
        void validate(const std::string& section = "HybridMetricMap") const;
    };

    /** Outcome of one insertScan(). */
    struct InsertStats
    {
        size_t beams = 0;             //!< beams considered
        size_t returns_stored = 0;    //!< returns assigned to a region
        size_t returns_outside = 0;   //!< returns in no region (see `unassigned`)
        size_t beyond_range = 0;      //!< returns farther than max_range_m (free space only)
        size_t regions_visited = 0;   //!< regions whose bounding box meets the scan's
        size_t regions_updated = 0;   //!< regions that received rays or returns
        size_t regions_degenerate = 0;  //!< skipped: current triangle no longer a valid frame
        std::vector<Eigen::Vector2d> unassigned;  //!< global positions of returns in no region
    };

    /** Throws std::invalid_argument on invalid options. */
    explicit HybridMetricMap(const Options& options);
    HybridMetricMap(const HybridMetricMap&) = delete;
    HybridMetricMap& operator=(const HybridMetricMap&) = delete;

    const Options& options() const { return options_; }

    /** Fuses one scan taken at `vehicle_pose` (estimate at observation time) into the
     *  regions of `partition`, whose current vertices must be up to date
     *  (RegionPartition::updateVertexPositions after the filter update). */
    InsertStats insertScan(
        const ScanPoints& scan, const mrpt::math::TPose2D& vehicle_pose,
        const hymm::ltr::RegionPartition& partition);

    /** Drops local maps of regions the partition no longer has; returns their ids. */
    std::vector<long> removeStaleRegions(const hymm::ltr::RegionPartition& partition);

    // --- global rendering at the current landmark estimates ------------------------
    /** Every stored return, mapped through its region's reference -> current map. */
    void renderPoints(
        const hymm::ltr::RegionPartition& partition, mrpt::maps::CSimplePointsMap& out) const;
    /** Occupancy at `resolution_m` over the bounding box of the current triangles that
     *  hold a grid; each cell centre reads the local cell of the region containing it
     *  (cells in no region stay at 0.5). */
    void renderOccupancy(
        const hymm::ltr::RegionPartition& partition, double resolution_m,
        mrpt::maps::COccupancyGridMap2D& out) const;
    /** Any layer kind into a map the caller sized (see DenseLayer::renderInto). */
    void renderLayer(
        const std::string& kind, const hymm::ltr::RegionPartition& partition,
        mrpt::maps::CMetricMap& out) const;

    // --- access ------------------------------------------------------------------
    size_t size() const { return maps_.size(); }
    /** nullptr if the region has no dense content yet. */
    const LocalDenseMap* localMap(long region_id) const;
    std::vector<long> regionIds() const;
    size_t memoryBytes() const;
    /** Empty layer of `kind` for a region (nullptr if the kind is unknown/disabled). */
    std::unique_ptr<DenseLayer> makeLayer(
        const std::string& kind, const hymm::ltr::TriangleFrame::Vertices& reference) const;
    mrpt::system::CTimeLogger& profiler() const { return profiler_; }

    // --- persistence -------------------------------------------------------------
    void save(std::ostream& out) const;
    /** Replaces the content; throws std::runtime_error on malformed input. */
    void load(std::istream& in);

private:
    LocalDenseMap& localMapFor(long region_id, const hymm::ltr::TriangleFrame::Vertices& reference);

    const Options options_;
    std::map<long, std::unique_ptr<LocalDenseMap>> maps_;
    mutable mrpt::system::CTimeLogger profiler_;
};

}  // namespace hymm::dense
