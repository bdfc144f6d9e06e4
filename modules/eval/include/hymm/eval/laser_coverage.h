/**
 * @file laser_coverage.h
 * @brief "What the laser saw": the part of the true object outlines that a run's laser
 *        actually observed, and how much of THAT part a dense map covers.
 *
 * A dense map can only hold what the sensor saw, so its coverage of the whole outlines
 * (dense::evaluateOutlines) mixes two things: surfaces never in view and surfaces seen
 * but lost by the mapping (e.g. returns that fell in no Local Triangular Region, thesis
 * Sec. 3.7.3). This separates them:
 *  1. every scan of the run is placed at the TRUE pose of its timestamp (the simulator's
 *     ground-truth path, nearest sample within a tolerance), with its own sensor
 *     mounting (dense::ScanPoints::toWorld), so the returns carry only the range noise;
 *  2. the outlines are sampled every `sample_step_m` exactly as dense::evaluateOutlines
 *     samples them; a sample is SEEN when a placed return lies within `radius_m`;
 *  3. a point set (the dense map) covers a sample with a point within `radius_m`; its
 *     coverage of the seen samples is covered-and-seen / seen.
 * With the same step and radius, coverageOfSeen().coverage (over all samples) equals
 * dense::evaluateOutlines(points, outlines).coverage.
 *
 * Cost: O(R log R) to index the R placed returns (an MRPT/nanoflann KD-tree) plus
 * O(S log R) for S samples; likewise for the map points.
 *
 * The dense map in the landmark frame. A HYMM dense map inherits the feature map's
 * error: every region is drawn on its estimated vertices, so after a single pass (no
 * loop closure) its points are off by the drift of the landmarks they hang from, which
 * the dense layers cannot change (UIF). pointsAtTrueVertices() draws each region on the
 * TRUE positions of its vertices instead, so the points carry only their own error
 * relative to the landmarks (local coordinates, thesis Sec. 3.3 and Appendix C): what
 * the dense layers, and the delayed store, are responsible for.
 */
#pragma once

#include <hymm/io/trajectory_io.h>
#include <hymm/dense/HybridMetricMap.h>
#include <hymm/dense/ScanPoints.h>
#include <hymm/dense/outline_metrics.h>

#include <Eigen/Core>
#include <limits>
#include <map>
#include <vector>

namespace hymm::eval
{
/** One laser scan of the run with its timestamp (rawlog time base, as the TUM path). */
struct TimedScan
{
    double t = 0;            //!< [s]
    dense::ScanPoints scan;  //!< returns in the sensor frame + the sensor mounting
};

struct LaserCoverageOptions
{
    double sample_step_m = 0.05;  //!< [m] outline sample spacing (as OutlineMetricsOptions)
    double radius_m = 0.3;        //!< [m] a sample is seen / covered within this distance
    bool closed = true;           //!< outlines are closed polygons
    /** [m] returns farther from the sensor are not counted as seen (the dense map keeps
     *  them as free space only, HybridMetricMap max_range_m); infinity: all. */
    double max_range_m = std::numeric_limits<double>::infinity();
    double time_tolerance_s = 1e-3;  //!< [s] scan-to-truth timestamp match

    /** Throws std::invalid_argument for non-positive step, radius, range or tolerance. */
    void validate() const;
};

/** Samples of the outlines and the outline each one lies on. */
struct OutlineSamples
{
    std::vector<Eigen::Vector2d> points;
    std::vector<size_t> outline;  //!< index into the outlines, parallel to `points`
};

/** Samples at s = 0, step, 2 step, ... < length along every segment (the next segment
 *  starts at the shared vertex), plus the end point of each open polyline: the rule of
 *  dense::evaluateOutlines. Throws std::invalid_argument if step <= 0. */
OutlineSamples sampleOutlines(const std::vector<dense::Polygon>& outlines, double step_m,
                              bool closed);

/** The returns of `scans` placed at the true poses of `true_path`. */
struct PlacedReturns
{
    std::vector<Eigen::Vector2d> points;  //!< global positions of the returns
    size_t scans_placed = 0;              //!< scans with a true pose within the tolerance
    size_t scans_unmatched = 0;           //!< skipped: no true pose within the tolerance
    size_t beyond_range = 0;              //!< returns farther than max_range_m (skipped)
};

/** Throws std::invalid_argument if `true_path` is empty or the options are invalid. */
PlacedReturns placeAtTruePoses(const std::vector<TimedScan>& scans,
                               const std::vector<io::StampedPose2D>& true_path,
                               const LaserCoverageOptions& options = LaserCoverageOptions());

/** Outline samples and which of them the laser saw. */
struct SeenOutline
{
    OutlineSamples samples;
    std::vector<char> seen;  //!< 1 if a placed return lies within radius_m, per sample
    size_t seen_samples = 0;
    double radius_m = 0;  //!< the radius used (coverageOfSeen uses it too)
    PlacedReturns returns;

    /** seen_samples / samples (0 without samples). */
    double seenFraction() const;
};

/** Steps 1-2 of the file comment. Throws std::invalid_argument if there is no outline
 *  segment, `true_path` is empty or the options are invalid. */
SeenOutline laserSeenOutline(const std::vector<TimedScan>& scans,
                             const std::vector<io::StampedPose2D>& true_path,
                             const std::vector<dense::Polygon>& outlines,
                             const LaserCoverageOptions& options = LaserCoverageOptions());

/** Coverage of the outline samples by a point set, overall and of the seen samples. */
struct SeenCoverage
{
    size_t samples = 0;
    size_t covered_samples = 0;
    size_t seen_samples = 0;
    size_t covered_seen_samples = 0;  //!< seen and covered
    double coverage = 0;              //!< covered / samples
    double seen_coverage = 0;         //!< covered-and-seen / seen (0 without seen samples)
    std::vector<char> covered;        //!< per sample
};

/** Step 3 of the file comment, with seen.radius_m. */
SeenCoverage coverageOfSeen(const SeenOutline& seen, const std::vector<Eigen::Vector2d>& points);

/**
 * True positions of the vertices of every region of `partition`: `landmarks` maps filter
 * landmark ids to their true positions (e.g. from an association with the ground
 * truth). A vertex missing there whose region's two other vertices are known (a virtual
 * landmark, thesis Sec. 3.5.1, defined by the edge it stands on) is placed at the same
 * position relative to that edge as its current estimate relative to the estimated
 * edge (metres along and across it from its midpoint, as ltr::virtualApex defines it;
 * a vertex shared by several regions is placed from the region with the lowest id, the
 * one it was created with). Vertices that remain unknown are left out.
 */
std::map<long, Eigen::Vector2d> trueRegionVertices(
    const ltr::RegionPartition& partition, const std::map<long, Eigen::Vector2d>& landmarks);

/** Points of the points layers with every region drawn on `vertices` (reference ->
 *  true triangle, the affine map of ltr::AffineRegionMap). */
struct LandmarkFramePoints
{
    std::vector<Eigen::Vector2d> points;
    size_t regions_drawn = 0;
    size_t regions_skipped = 0;  //!< a vertex without a true position, or a folded triangle
    size_t points_skipped = 0;   //!< held by the skipped regions
};

LandmarkFramePoints pointsAtTrueVertices(const dense::HybridMetricMap& map,
                                         const ltr::RegionPartition& partition,
                                         const std::map<long, Eigen::Vector2d>& vertices);

}  // namespace hymm::eval
