/**
 * @file run_metrics.h
 * @brief Metrics of one SLAM run against ground truth: path error, vehicle NEES per
 *        step, landmark errors and landmark NEES, from the estimates alone (any
 *        program's: hymm-slam's pipeline hands its path and landmarks in, hymm-eval
 *        its result files).
 */
#pragma once

#include <hymm/eval/LandmarkEvaluator.h>
#include <hymm/eval/MetricsJson.h>
#include <hymm/io/ground_truth_io.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace hymm::eval
{
/** One estimated vehicle pose (x, y, phi) with its covariance. */
struct EstimatedPose
{
    double t = 0;  //!< [s]
    Eigen::Vector3d pose = Eigen::Vector3d::Zero();
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
};

/** The poses without their covariances. */
std::vector<io::StampedPose2D> stampedPoses(const std::vector<EstimatedPose>& path);

/**
 * NEES of every path sample against the ground-truth path (3 DOF: x, y, phi), NaN where
 * no true pose matches (timestamps within `time_tolerance`, or by index when the truth
 * has none) or the covariance is singular. One entry per path sample.
 */
std::vector<double> vehicleNeesSeries(const std::vector<EstimatedPose>& path,
                                      const io::GroundTruth& gt, double time_tolerance = 1e-3);

/**
 * Appends to `j` (each only when the truth holds what it needs):
 *  - "path": RMSE / mean / max position error, heading RMSE (TrajectoryEvaluator);
 *  - "vehicle_nees": mean of the per-step NEES, steps, the single-run 95% band for
 *    3 DOF and the fraction of steps inside it;
 *  - "landmarks": mean / max error, unmatched counts, mean landmark NEES;
 *  - "landmark_nees": the 2-DOF band and the fraction of landmarks inside it.
 */
void writeRunMetrics(MetricsJson& j, const std::vector<EstimatedPose>& path,
                     const std::vector<LandmarkEstimate>& landmarks,
                     LandmarkEvaluator::Association association, const io::GroundTruth& gt);

/**
 * Scores result files written by any SLAM program (hymm-slam, MRPT kf-slam, ...)
 * against ground truth with the path and landmark metrics of writeRunMetrics(): path
 * file (TUM), optional landmark CSV "id,x,y[,cxx,cxy,cyy]". Used by the hymm-eval app.
 */
MetricsJson evaluateResultFiles(const std::string& path_tum, const std::string& landmarks_csv,
                                const io::GroundTruth& gt);

}  // namespace hymm::eval
