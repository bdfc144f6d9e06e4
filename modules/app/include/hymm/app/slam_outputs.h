/**
 * @file slam_outputs.h
 * @brief What hymm-slam writes: the estimated path and landmarks, the map figure,
 *        a run summary, the dense maps, and metrics against ground truth (path RMSE,
 *        landmark errors, NEES statistics with chi-square bounds: hymm::eval's run
 *        metrics; outline metrics of every dense map).
 *
 * Sources: run_outputs.cpp (path, landmarks, figure, timing, run metrics), summary.cpp,
 * dense_outputs.cpp (the dense maps: each layer kind's files, counters, scored points and
 * summary line come from its output hooks, dense::LayerKind::outputs).
 */
#pragma once

#include <hymm/app/MapPlot.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/eval/LandmarkEvaluator.h>
#include <hymm/eval/MetricsJson.h>
#include <hymm/eval/run_metrics.h>
#include <hymm/io/ground_truth_io.h>

#include <string>

namespace hymm::app
{
using denseslam::DenseSlam;
using io::GroundTruth;

/** The path samples with their covariances, for hymm::eval's run metrics. */
std::vector<eval::EstimatedPose> estimatedPoses(const DenseSlam& slam);

/** Landmark matching for metrics: by ID when the run used the rawlog's landmark IDs
 *  (then estimate and truth share them), otherwise nearest neighbour. */
eval::LandmarkEvaluator::Association landmarkAssociationFor(const DenseSlam& slam);

/** The estimated 2-DOF landmarks with their covariances. */
std::vector<eval::LandmarkEstimate> estimatedLandmarks(const ekf::EkfSlam& ekf);

/** TUM file of the path samples. */
void writeEstimatedPath(const DenseSlam& slam, const std::string& file);

/** id,x,y,cxx,cxy,cyy of every 2-DOF landmark. */
void writeEstimatedLandmarks(const ekf::EkfSlam& ekf, const std::string& file);

/** Figure data: estimated path and landmarks, plus the truth when given. */
MapPlot makeMapPlot(const DenseSlam& slam, const GroundTruth* gt);

/**
 * Metrics against ground truth, as a JSON object: run time, steps, landmark count, the
 * extraction counters (landmarks from the laser), then eval::writeRunMetrics (path and
 * landmark errors, vehicle and landmark NEES against their chi-square bands).
 */
eval::MetricsJson computeMetrics(const DenseSlam& slam, const GroundTruth& gt, double run_seconds);

/** A Scan-SLAM landmark's estimate (scan_landmark_outputs.cpp). */
struct ScanLandmarkEstimate
{
    long id = -1;
    Eigen::Vector3d pose = Eigen::Vector3d::Zero();  //!< template frame (x, y, phi)
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    std::vector<Eigen::Vector2d> points;  //!< template points at `pose` (global)
};

/** Every scan landmark in the filter (none without landmark_source scan_landmarks). */
std::vector<ScanLandmarkEstimate> scanLandmarkEstimates(const DenseSlam& slam);

/** CSV "id,x,y,phi,cxx,cxy,cxphi,cyy,cyphi,cphiphi,points" of the scan landmarks
 *  (pose, 3x3 covariance, template point count). */
void writeScanLandmarks(const DenseSlam& slam, const std::string& file);

/** Templates, local axes and 3-sigma ellipses of the scan landmarks in the map figure. */
void addScanLandmarksToPlot(const DenseSlam& slam, MapPlot& plot);

/** "scan_sources": every registered source's counters (nothing when none is in use). */
void writeScanSourceMetrics(eval::MetricsJson& j, const DenseSlam& slam);

/** One summary line of the registered sources' counters (nothing when none is in use). */
void writeScanSourceSummary(std::ostream& f, const DenseSlam& slam);

/** "hll": the high-level landmarks' counters (proposed, accepted, initialised, updated,
 *  rejections by reason, alignments); nothing unless [HighLevelLandmarks] is on. */
void writeHllMetrics(eval::MetricsJson& j, const DenseSlam& slam);
/** One summary line of the HLL counters (nothing unless they are on). */
void writeHllSummary(std::ostream& f, const DenseSlam& slam);
/** hll.csv (one line per HLL: detection, template, landmark, pose now, half extents)
 *  and, with `png`, hll.png: the occupancy layer with corners, candidate and accepted
 *  rectangles and the HLLs' axes (thesis Fig. 6.5). `dir` ends with a separator. */
void writeHllOutputs(const DenseSlam& slam, const std::string& dir, bool png);

/** Wall-clock cost of processing one sensory frame (or single observation). */
struct FrameTiming
{
    size_t entry = 0;         //!< rawlog entry index (1-based)
    size_t landmarks = 0;     //!< map size after the frame
    size_t observations = 0;  //!< landmark observations used in the frame
    double seconds = 0;       //!< processing time of the frame
};

/** CSV "entry,landmarks,observations,seconds", one line per frame. */
void writeTiming(const std::vector<FrameTiming>& timing, const std::string& file);

/** True object outlines from the simulator's `<name>_gt_objects.txt` (every record;
 *  hymm::sim::readObjectOutlines). Throws if the file is missing or malformed. */
std::vector<dense::Polygon> loadObjectOutlines(const std::string& file);

/**
 * Dense-map outputs (only what the run built), into the folder `dir`: each enabled layer
 * kind's files, written by its output hooks (modules/dense/README.md, "Files of each
 * layer kind"); classic_grid.png and classic_grid.gridmap, the classic baseline;
 * regions.txt (RegionPartition::save). `png` = false skips the images. Throws if a file
 * cannot be written.
 */
void writeDenseOutputs(const DenseSlam& slam, const std::string& dir, bool png = true);

/** A true point landmark as the laser sees it: a trunk of `radius` [m] (0: a point). */
struct TrueTrunk
{
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    double radius = 0;
};

/** Trunks of the ground-truth landmarks: the radius is the record's first extra column
 *  (HYMM's simulator writes "id,x,y,radius"), 0 when the file has none. */
std::vector<TrueTrunk> trueTrunks(const std::vector<io::LandmarkRecord>& landmarks);

/**
 * Accuracy and coverage of every dense map the run built (dense module's
 * evaluateOutlines), into `j` under "dense": "points" (every rendered point),
 * "occupancy" and "classic_grid" (centres of cells with P(occupied) > 0.8), "particles"
 * (particles with weight > 0.8), "sog" (the Gaussian means) and "property" (centres of
 * the rendered cells holding a value: where the layer has content, not its values),
 * each with points, mean_distance_m and p95_distance_m (distance of each map point to
 * the nearest true surface: the object outlines and the trunks of `true_landmarks`,
 * since the laser sees both), coverage and outline_samples (of the object outlines
 * only: a sample is covered with a map point within 0.3 m). Outline metrics need
 * `outlines`; always written (with dense layers on): region and return counters,
 * "memory_bytes_by_kind", and per enabled layer "items" (DenseLayer::size() summed) and
 * "memory_bytes"; occupancy: regions_coarse / regions_fine (occupancy_regions.csv
 * has the content of each region); particles: particles (rendered),
 * occupied_min_weight (0.8), weight_fraction_above_0_8, weight_fraction_below_0_5
 * (thesis Sec. 4.2.3 reports 87% / 2%); sog: gaussians; property: cells (local),
 * rendered_cells and, when empty although returns were stored, a "note" saying so.
 */
void writeDenseMetrics(eval::MetricsJson& j, const DenseSlam& slam,
                       const std::vector<dense::Polygon>& outlines,
                       const std::vector<TrueTrunk>& true_landmarks = {});

/**
 * Run-level warnings: a run that cannot have done what was asked although every entry
 * read cleanly. One sentence each, for stderr and summary.txt:
 *  - the rawlog held no observation, or none of them was used (of a class this config
 *    does not use, e.g. bearing-range readings under a laser-landmark config, or of a
 *    class DenseSlam does not read: 3D scans, images, GPS...), or most were not used;
 *  - no landmark observation reached the filter;
 *  - no odometry (no prediction over several frames);
 *  - frame time stamps went backwards.
 * Empty for a healthy run. hymm-slam --strict fails on any of them.
 */
std::vector<std::string> runWarnings(const DenseSlam& slam);

/** Human-readable counters and timing; with dense layers one line per enabled layer
 *  (what it holds and its memory). Observations of unsupported classes (by class name),
 *  frames out of time order and `warnings` get lines when there are any. */
void writeSummary(const DenseSlam& slam, double run_seconds, size_t entries,
                  const std::string& file, const std::vector<std::string>& warnings = {});

}  // namespace hymm::app
