/**
 * @file RegionPartition.h
 * @brief The set of Local Triangular Regions and its growth (thesis Sec. 3.2-3.5).
 *
 * The partition covers the explored area with triangles whose vertices are feature-
 * map landmarks (Fig. 3.1). It grows as the vehicle explores: update() proposes
 * candidates among landmarks near the vehicle, checks them with BaseConditionChecker
 * (Sec. 3.5) and adds those that pass. Candidates come, in order of preference, from
 *  1. boundary edges of existing regions near the vehicle (edges used by one region):
 *     the third vertex is taken on the free side of the edge, preferring the landmark
 *     that sees the edge under the largest angle (the Delaunay choice: its
 *     circumcircle holds no other candidate on that side), so neighbouring regions
 *     share whole edges and the area is covered without gaps;
 *  2. when no edge can grow, a seed: the Delaunay-empty triangle of eligible landmarks
 *     nearest to the vehicle.
 * A candidate that contains another nearby landmark is skipped.
 *
 * Each region keeps its reference triangle (vertex positions at creation) and the
 * current vertex positions. Invariant of the point lookup: a uniform grid indexes the
 * bounding box of every region's `current` triangle as of that region's last refresh;
 * lookups (findRegion/findRegions/regionsInBox) visit the grid cells of the query and
 * test only the regions listed there, never all regions.
 *
 * Refreshing the current vertices after the feature map changed:
 *  - update() and updateVertexPositions() re-read every region (O(regions)), and
 *    update() scans every landmark id (O(landmarks)): exact everywhere;
 *  - updateNear() and refreshNear() re-read only the regions whose box meets a window
 *    around the vehicle, and updateNear() asks the view for the landmarks near the
 *    vehicle (LandmarkCovarianceView::idsNear): the per-step cost depends on the area
 *    around the vehicle, not on the size of the map (thesis: the dense layers add O(1)
 *    per step). Regions outside the window keep the positions of their last refresh,
 *    which is what the dense layers store against (local coordinates never change);
 *    call updateVertexPositions() before reading far regions (rendering the global map,
 *    after a loop closure, before saving). Options::local_refresh tells the pipeline
 *    which of the two to use.
 *
 * Text save/load round-trips all regions (ids, vertex ids, reference and current
 * vertices, creation times) exactly.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include "hymm/ltr/AffineRegionMap.h"
#include "hymm/ltr/BaseConditionChecker.h"
#include "hymm/ltr/LandmarkCovarianceView.h"
#include "hymm/ltr/TriangleFrame.h"

#include <mrpt/config/CLoadableOptions.h>

#include <array>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace mrpt::serialization
{
class CArchive;
}

namespace hymm::ltr
{
/** One LTR. */
struct Region
{
    long id = -1;
    std::array<long, 3> vertex_ids{{-1, -1, -1}};  //!< landmark ids of L1, L2, L3
    TriangleFrame::Vertices reference;             //!< vertex positions at creation
    TriangleFrame::Vertices current;               //!< vertex positions at the last refresh
    double creation_time = 0;                      //!< [s] time stamp given to update()
};

class RegionPartition
{
public:
    /** Ini section [LtrPartition]: these keys plus BaseConditionChecker::Options::keys();
     *  unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        BaseConditionChecker::Options conditions;  //!< Sec. 3.5 conditions
        double search_radius_m = 25.0;  //!< [m] candidate vertices lie this close to the vehicle
        double grid_cell_size_m = 10.0;  //!< [m] cell of the point-lookup grid
        int max_new_regions_per_update = 16;  //!< bound on work per update()
        int max_seed_landmarks = 8;  //!< nearest eligible landmarks tried when seeding (>= 3)
        /** Pipeline (DenseSlam): grow with updateNear() (O(area around the vehicle) per
         *  step) instead of update() (O(regions + landmarks)); far regions are then
         *  refreshed by updateVertexPositions() only after a large correction (and by
         *  DenseSlam::refreshRegions() before the global map is rendered). */
        bool local_refresh = true;
        /** [m] with local_refresh: a vehicle correction (update minus prediction) larger
         *  than this is treated as a loop closure and every region is refreshed. */
        double full_refresh_correction_m = 1.0;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "LtrPartition") const;
    };

    /** Throws std::invalid_argument on invalid options. */
    explicit RegionPartition(const Options& options);
    RegionPartition(const RegionPartition&) = delete;
    RegionPartition& operator=(const RegionPartition&) = delete;

    const Options& options() const { return options_; }
    const BaseConditionChecker& checker() const { return checker_; }

    /** Refreshes current vertex positions from `view`, then grows the partition around
     *  view.vehiclePose(). Returns the ids of the regions created, in creation order. */
    std::vector<long> update(const LandmarkCovarianceView& view, double time);

    /** Checks one explicit candidate against all conditions (overlap against the
     *  current triangles) and adds it if it passes. Returns the check and, on success,
     *  the new region id in `id`. Call updateVertexPositions() first if the map moved. */
    CheckResult tryAddRegion(
        const std::array<long, 3>& ids, const LandmarkCovarianceView& view, double time,
        long* id = nullptr);

    /** update() limited to the area around view.vehiclePose(): refreshes the regions
     *  whose box meets the square of half-side max(search_radius_m, refresh_radius_m)
     *  + grid_cell_size_m around the vehicle (refreshNear), and grows from the
     *  landmarks view.idsNear(vehicle, search_radius_m). `refresh_radius_m`: how far
     *  from the vehicle the caller will look regions up before the next update (scan
     *  range plus sensor offset); the extra grid cell absorbs the drift of regions
     *  refreshed in earlier steps. Creates the same regions as update() as long as no
     *  region outside the window moved into it since its last refresh (a loop closure:
     *  call updateVertexPositions() first). Cost: O(regions and landmarks near the
     *  vehicle) plus one pass of idsNear(). */
    std::vector<long> updateNear(
        const LandmarkCovarianceView& view, double time, double refresh_radius_m = 0);

    /** Re-reads the current vertex positions of every region and updates the lookup
     *  grid (O(number of regions)). Vertices no longer in `view` keep their last
     *  position; regionsWithMissingLandmarks() lists them. */
    void updateVertexPositions(const LandmarkCovarianceView& view);
    /** updateVertexPositions() for the regions whose box (as of their last refresh)
     *  meets the square of half-side `radius` around `centre`; O(regions there). */
    void refreshNear(
        const LandmarkCovarianceView& view, const Eigen::Vector2d& centre, double radius);
    /** Regions with a vertex that `view` no longer has (candidates for removal). */
    std::vector<long> regionsWithMissingLandmarks(const LandmarkCovarianceView& view) const;
    /** regionsWithMissingLandmarks() among the regions whose box meets the square of
     *  half-side `radius` around `centre`, sorted by id. */
    std::vector<long> regionsWithMissingLandmarksNear(
        const LandmarkCovarianceView& view, const Eigen::Vector2d& centre, double radius) const;

    // --- lookup -------------------------------------------------------------------
    /** A region whose current triangle contains `p` (closed, lowest id on shared
     *  borders), or nullopt. */
    std::optional<long> findRegion(const Eigen::Vector2d& p) const;
    /** All regions whose current triangle contains `p` (more than one only on shared
     *  edges/vertices), sorted by id. */
    std::vector<long> findRegions(const Eigen::Vector2d& p) const;
    /** Regions whose current bounding box intersects the given box. */
    std::vector<long> regionsInBox(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) const;

    // --- access -------------------------------------------------------------------
    size_t size() const { return regions_.size(); }
    bool has(long id) const { return regions_.count(id) != 0; }
    /** Throws std::out_of_range for an unknown id. */
    const Region& region(long id) const;
    std::vector<long> regionIds() const;
    /** Regions that have `landmark_id` as a vertex, sorted by id. */
    std::vector<long> regionsUsingLandmark(long landmark_id) const;
    /** Regions sharing a whole edge (two vertex ids) with `id`. */
    std::vector<long> edgeNeighbours(long id) const;

    TriangleFrame referenceFrame(long id) const;
    /** Throws std::invalid_argument if the current triangle became degenerate. */
    TriangleFrame currentFrame(long id) const;
    /** Reference -> current affine map of region `id`. */
    AffineRegionMap referenceToCurrent(long id) const;

    // --- removal ------------------------------------------------------------------
    bool removeRegion(long id);
    /** Removes every region using `landmark_id` (e.g. the landmark was pruned). */
    std::vector<long> removeRegionsUsingLandmark(long landmark_id);
    void clear();

    // --- persistence --------------------------------------------------------------
    void save(std::ostream& out) const;
    /** Replaces the content; throws std::runtime_error with the line number on a
     *  malformed stream. */
    void load(std::istream& in);
    /** Saved run state (hymm-slam --save-state): every member a later step reads, bit
     *  for bit; loadState() replaces them (options come from the config). Throws
     *  std::runtime_error on a corrupt or truncated state. Source: RegionPartitionState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);
    void saveToFile(const std::string& path) const;
    void loadFromFile(const std::string& path);

private:
    using EdgeKey = std::pair<long, long>;
    static EdgeKey edgeKey(long a, long b) { return a < b ? EdgeKey{a, b} : EdgeKey{b, a}; }
    std::int64_t cellKey(long ix, long iy) const;
    void cellRange(const TriangleFrame::Vertices& v, long& x0, long& y0, long& x1, long& y1) const;
    void indexRegion(const Region& r);
    void unindexRegion(const Region& r);
    /** Re-reads r.current from `view`; moves r in the grid if its cells changed. */
    void refreshRegion(Region& r, const LandmarkCovarianceView& view);
    long insertRegion(Region r);
    std::vector<TriangleFrame::Vertices> nearbyTriangles(const TriangleFrame::Vertices& v) const;

    /** Steps 2-3 of update(): grows around the vehicle from the landmarks within
     *  search_radius_m (view.idsNear), current vertices already refreshed. */
    std::vector<long> grow(const LandmarkCovarianceView& view, double time);
    // growth helpers (RegionPartitionGrowth.cpp)
    struct Neighbourhood;  // landmarks near the vehicle for one update()
    bool growFromEdges(
        const LandmarkCovarianceView& view, const Neighbourhood& nb, double time,
        std::vector<EdgeKey>& failed_edges, std::vector<long>& created);
    bool seed(
        const LandmarkCovarianceView& view, const Neighbourhood& nb, double time,
        std::vector<long>& created);
    bool containsOtherLandmark(
        const TriangleFrame::Vertices& tri, const std::array<long, 3>& ids,
        const LandmarkCovarianceView& view, const std::vector<long>& nearby) const;

    const Options options_;
    const BaseConditionChecker checker_;
    std::map<long, Region> regions_;
    std::map<EdgeKey, std::vector<long>> edges_;
    std::unordered_map<long, std::vector<long>> by_landmark_;
    std::unordered_map<std::int64_t, std::vector<long>> grid_;
    long next_id_ = 0;
};

}  // namespace hymm::ltr
