/**
 * @file metrics_report.h
 * @brief Puts evaluation results into a MetricsJson object under fixed, documented keys,
 *        so every app and benchmark reports the same names.
 *
 * Trajectory keys: matched, unmatched, position_rmse_m, position_mean_m, position_max_m,
 * heading_rmse_deg, heading_max_deg, aligned, and when aligned an "alignment" object
 * {x_m, y_m, phi_deg}. Landmark keys: association, matched, unmatched_estimates,
 * unmatched_truth, mean_error_m, rmse_m, max_error_m, nees_count, nees_singular, mean_nees.
 * Relative pose error keys: pairs, translation_{mean,median,max}_m, rotation_{mean,median,max}_deg.
 */
#pragma once

#include <hymm/eval/LandmarkEvaluator.h>
#include <hymm/eval/MetricsJson.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <hymm/eval/relative_pose_error.h>

namespace hymm::eval
{
void writeTrajectoryMetrics(MetricsJson& out, const TrajectoryEvaluator::Result& r);
void writeLandmarkMetrics(MetricsJson& out, const LandmarkEvaluator::Result& r);
void writeRelativePoseMetrics(MetricsJson& out, const RelativePoseError& r);

}  // namespace hymm::eval
