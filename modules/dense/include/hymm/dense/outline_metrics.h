/**
 * @file outline_metrics.h
 * @brief Accuracy and coverage of a dense map against true object outlines
 *        (the evidence behind Fig. 4.3: classic OG vs OG-DenseSLAM).
 *
 * Given map points (raw returns, or centres of cells with P(occ) > 0.8 as in Fig. 4.3)
 * and the true outlines as polygons:
 *  - accuracy: distance of each map point to the nearest outline segment; mean and
 *    95th percentile (nearest-rank: the ceil(0.95 n)-th smallest distance);
 *  - coverage: outlines sampled every sample_step_m along their length; the fraction
 *    of samples with a map point within coverage_radius_m.
 */
#pragma once

#include <Eigen/Core>

#include <vector>

namespace mrpt::maps
{
class CPointsMap;
class COccupancyGridMap2D;
}  // namespace mrpt::maps

namespace hymm::dense
{
using Polygon = std::vector<Eigen::Vector2d>;

struct OutlineMetricsOptions
{
    double sample_step_m = 0.05;     //!< [m] spacing of outline samples for coverage
    double coverage_radius_m = 0.3;  //!< [m] an outline sample is covered within this
    bool closed = true;              //!< outlines are closed polygons (last -> first edge)
};

struct OutlineMetrics
{
    size_t points = 0;           //!< map points evaluated
    double mean_distance_m = 0;  //!< NaN without points
    double p95_distance_m = 0;   //!< NaN without points
    size_t outline_samples = 0;
    size_t covered_samples = 0;
    double coverage = 0;  //!< covered_samples / outline_samples
};

/** A circle (e.g. a true trunk) as a closed polygon of `sides` sides; 32 keep it within
 *  r (1 - cos(pi/32)) = 0.5% of r of the circle. r <= 0 gives the centre (a degenerate
 *  segment, so distances to it are distances to the point). */
Polygon circlePolygon(const Eigen::Vector2d& centre, double radius, int sides = 32);

/** Throws std::invalid_argument for non-positive step/radius or no outline segment. */
OutlineMetrics evaluateOutlines(
    const std::vector<Eigen::Vector2d>& points, const std::vector<Polygon>& outlines,
    const OutlineMetricsOptions& options = OutlineMetricsOptions());

/** x, y of every point of an MRPT points map. */
std::vector<Eigen::Vector2d> pointsOf(const mrpt::maps::CPointsMap& map);
/** Centres of the cells with P(occupied) > `min_probability`. */
std::vector<Eigen::Vector2d> occupiedCellCentres(
    const mrpt::maps::COccupancyGridMap2D& grid, double min_probability = 0.8);

}  // namespace hymm::dense
