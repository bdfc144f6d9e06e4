/**
 * @file slam_outputs.h
 * @brief What hymm-slam writes: the estimated path and landmarks, the map figure,
 *        a run summary, and metrics against ground truth (path RMSE, landmark
 *        errors, NEES statistics with chi-square bounds).
 */
#pragma once

#include <hymm/denseslam/DenseSlam.h>
#include <hymm/denseslam/MapPlot.h>
#include <hymm/eval/ground_truth_io.h>
#include <hymm/eval/MetricsJson.h>

#include <string>

namespace hymm::denseslam
{
using eval::GroundTruth;

/**
 * Loads ground truth in either supported format, chosen per file:
 *  - MRPT simul-landmarks (`*_ground_truth_robot_path.txt`, `*_ground_truth.txt`):
 *    the path has no timestamps; row i is matched with the i-th estimated pose;
 *  - HYMM (TUM path, `id,x,y,...` landmark CSV): matched by timestamp.
 * Either file may be empty (not given). Throws on unreadable or malformed files.
 */
GroundTruth loadGroundTruth(const std::string& path_file, const std::string& landmarks_file);

/** TUM file of the path samples. */
void writeEstimatedPath(const DenseSlam& slam, const std::string& file);

/** id,x,y,cxx,cxy,cyy of every 2-DOF landmark. */
void writeEstimatedLandmarks(const ekf::EkfSlam& ekf, const std::string& file);

/** Figure data: estimated path and landmarks, plus the truth when given. */
MapPlot makeMapPlot(const DenseSlam& slam, const GroundTruth* gt);

/**
 * Metrics against ground truth, as a JSON object:
 *  - "path": RMSE / mean / max position error, heading RMSE (eval::TrajectoryEvaluator);
 *  - "landmarks": mean / max error, unmatched counts, mean landmark NEES;
 *  - "nees": vehicle NEES per step summarised (mean, fraction of steps inside the 95%
 *    chi-square band for 3 DOF), landmark NEES fraction inside the 2-DOF band.
 */
eval::MetricsJson computeMetrics(const DenseSlam& slam, const GroundTruth& gt, double run_seconds);

/** Human-readable counters and timing. */
void writeSummary(const DenseSlam& slam, double run_seconds, size_t entries,
                  const std::string& file);

}  // namespace hymm::denseslam
