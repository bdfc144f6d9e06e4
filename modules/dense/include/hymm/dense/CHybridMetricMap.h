/**
 * @file CHybridMetricMap.h
 * @brief The hybrid metric map as an mrpt::maps::CMetricMap: what MRPT's map tools,
 *        CMultiMetricMap and its particle filters (CMonteCarloLocalization2D) can use.
 *
 * A HYMM map is the LTR partition (regions with their reference and current vertex
 * positions, thesis Sec. 3.2), the dense layers stored in each region's reference frame
 * (HybridMetricMap) and the landmark estimates the regions hang on. This class owns a
 * copy of the three, frozen at the landmark estimates it was given (the current vertices
 * of the partition): outside a SLAM filter nobody moves the landmarks, so the map is
 * rendered once at those estimates.
 *
 *  - insertObservation(): a CObservation2DRangeScan taken at the given robot pose is
 *    fused into the regions it covers (HybridMetricMap::insertScan); returns in no region
 *    are dropped (no filter grows new regions here). Other observations are ignored.
 *  - computeObservationLikelihood(): of a CObservation2DRangeScan, MRPT's own sensor
 *    model (COccupancyGridMap2D::computeObservationLikelihood, likelihood field by
 *    default, `likelihoodOptions`) evaluated on the occupancy layer rendered at the
 *    current landmark estimates (HybridMetricMap::renderOccupancy), or, without an
 *    occupancy layer, CPointsMap's model on the rendered points layer. The rendering is
 *    cached and redone after an insertion.
 *  - getVisualizationInto(): named objects that SceneViewer3D lists and can toggle:
 *    "ltr_triangles", "landmarks" (3-sigma ellipses), and one per enabled layer:
 *    "occupancy" (a textured plane), "points", "particles" (coloured by weight), "sog"
 *    (1-sigma ellipses), "property" (coloured cell centres).
 *  - saveMetricMapRepresentationToFile(prefix): prefix_occupancy.png (when the layer is
 *    on), prefix_points.txt, prefix_landmarks.txt, prefix_regions.txt.
 *  - CSerializable: options (ini text of [HybridMetricMap], the layer sections and
 *    [LtrPartition]), the partition and dense layers (their text save()), the landmarks
 *    (id, mean, covariance), the likelihood options, and with fallback tiles
 *    (FallbackTiles.h) their text (HybridMetricMap::saveFallbackTiles). A map without
 *    tiles is written as version 0 (the format of earlier HYMM, which reads it), one
 *    with tiles as version 1; both are read. Copies (assign, copy construction) keep
 *    the tiles too.
 *
 * Registered for MRPT's map factory as "CHybridMetricMap" and "HybridMetricMap" once
 * registerHybridMetricMap() has run (call it before reading a file or an .ini: a static
 * library drops unreferenced objects, and with them their registration). In a
 * CMultiMetricMap .ini:
 *   [MAP] HybridMetricMap_count = 1
 *   [MAP_HybridMetricMap_00]           map_file, likelihood_resolution_m
 *   [MAP_HybridMetricMap_00_likelihoodOpts]  COccupancyGridMap2D::TLikelihoodOptions keys
 *   [MAP_HybridMetricMap_00_HybridMetricMap] the [HybridMetricMap] keys for an empty map
 * (modules/dense/README.md lists the keys).
 */
#pragma once

#include "hymm/dense/HybridMetricMap.h"
#include "hymm/ltr/RegionPartition.h"

#include <mrpt/maps/CMetricMap.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/maps/TMetricMapTypesRegistry.h>
#include <mrpt/opengl/CSetOfObjects.h>

#include <Eigen/Core>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace hymm::dense
{
class CHybridMetricMap : public mrpt::maps::CMetricMap
{
    DEFINE_SERIALIZABLE(CHybridMetricMap, hymm::dense)

public:
    /** A landmark estimate the regions hang on (drawn with its 3-sigma ellipse). */
    struct Landmark
    {
        long id = -1;
        Eigen::Vector2d mean = Eigen::Vector2d::Zero();
        Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    };

    /** An empty map with default options (no regions: nothing can be inserted). */
    CHybridMetricMap();
    /** An empty map of these dense options. Throws std::invalid_argument if invalid. */
    explicit CHybridMetricMap(const HybridMetricMap::Options& options);
    CHybridMetricMap(const CHybridMetricMap& other);
    CHybridMetricMap& operator=(const CHybridMetricMap& other);
    ~CHybridMetricMap() override;

    /** Replaces the content by a copy of a partition (its current vertices are the
     *  landmark estimates the map is rendered at), its dense layers and the landmarks. */
    void assign(const hymm::ltr::RegionPartition& partition, const HybridMetricMap& dense,
                std::vector<Landmark> landmarks);

    const hymm::ltr::RegionPartition& partition() const { return *partition_; }
    const HybridMetricMap& dense() const { return *dense_; }
    const std::vector<Landmark>& landmarks() const { return landmarks_; }

    /** MRPT's range-scan sensor model used by computeObservationLikelihood(). */
    mrpt::maps::COccupancyGridMap2D::TLikelihoodOptions likelihoodOptions;
    /** [m] cell of the occupancy rendering the likelihood reads; 0 = the occupancy
     *  layer's cell_size_m. */
    double likelihood_resolution_m = 0;

    /** The occupancy layer rendered at the current landmark estimates (cached), in
     *  MRPT's convention (cell value = P(free), freeProbabilityGrid()); empty grid when
     *  the layer is off or holds nothing. */
    const mrpt::maps::COccupancyGridMap2D& renderedOccupancy() const;
    /** The points layer rendered at the current landmark estimates (cached). */
    const mrpt::maps::CSimplePointsMap& renderedPoints() const;

    /** MRPT-serialised, gzip-compressed file (what hymm-slam writes as map.hymm).
     *  Throws std::runtime_error if it cannot be written. */
    void saveToFile(const std::string& path) const;
    /** Reads a file written by saveToFile(); throws std::runtime_error with the reason
     *  (missing file, another class, another format version, truncated). */
    static CHybridMetricMap::Ptr loadFromFile(const std::string& path);

    // --- CMetricMap ---------------------------------------------------------------
    bool isEmpty() const override;
    std::string asString() const override;
    void getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const override;
    void saveMetricMapRepresentationToFile(const std::string& prefix) const override;

    // clang-format off
    MAP_DEFINITION_START(CHybridMetricMap)
    std::string map_file;  //!< saved map (saveToFile) to start from; empty = an empty map
    double likelihood_resolution_m = 0;  //!< see CHybridMetricMap::likelihood_resolution_m
    mrpt::maps::COccupancyGridMap2D::TLikelihoodOptions likelihoodOpts;
    HybridMetricMap::Options dense_options;  //!< used only without map_file
    MAP_DEFINITION_END(CHybridMetricMap)
    // clang-format on

private:
    void internal_clear() override;
    bool internal_insertObservation(
        const mrpt::obs::CObservation& obs,
        const std::optional<const mrpt::poses::CPose3D>& robotPose = std::nullopt) override;
    double internal_computeObservationLikelihood(
        const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const override;
    bool internal_canComputeObservationLikelihood(const mrpt::obs::CObservation& obs) const override;

    /** Copies everything of `other` (text round trip of partition and layers). */
    void copyFrom(const CHybridMetricMap& other);
    void invalidateCache();

    std::unique_ptr<hymm::ltr::RegionPartition> partition_;
    std::unique_ptr<HybridMetricMap> dense_;
    std::vector<Landmark> landmarks_;

    // Renderings at the current landmark estimates, built on first use.
    mutable std::mutex cache_mutex_;
    mutable std::unique_ptr<mrpt::maps::COccupancyGridMap2D> grid_cache_;
    mutable std::unique_ptr<mrpt::maps::CSimplePointsMap> points_cache_;
};

/** HybridMetricMap::renderOccupancy() and the classic grid write P(occupied) into the
 *  cells; MRPT's grids (its sensor models, observations2map, SceneViewer3D, .gridmap
 *  readers) read a cell as P(free) (0 = certainly occupied). This copy holds
 *  1 - P(occupied): the grid as MRPT understands it. */
mrpt::maps::COccupancyGridMap2D freeProbabilityGrid(const mrpt::maps::COccupancyGridMap2D& occupied);

/** "landmarks": a 3-sigma ellipse per landmark ("landmark_<id>") and the means
 *  ("landmark_means"), as getVisualizationInto() draws them. */
std::shared_ptr<mrpt::opengl::CSetOfObjects> landmarksObject(
    const std::vector<CHybridMetricMap::Landmark>& landmarks);

/** Registers CHybridMetricMap with MRPT's class registry (deserialisation by name) and
 *  map factory (CMultiMetricMap .ini sections). Idempotent; call before reading. */
void registerHybridMetricMap();

}  // namespace hymm::dense
