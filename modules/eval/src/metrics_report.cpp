#include "hymm/eval/metrics_report.h"

namespace hymm::eval
{
namespace
{
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
}  // namespace

void writeTrajectoryMetrics(MetricsJson& out, const TrajectoryEvaluator::Result& r)
{
    out.set("matched", r.matched);
    out.set("unmatched", r.unmatched);
    out.set("position_rmse_m", r.position_rmse);
    out.set("position_mean_m", r.position_mean);
    out.set("position_max_m", r.position_max);
    out.set("heading_rmse_deg", r.heading_rmse * kRadToDeg);
    out.set("heading_max_deg", r.heading_max * kRadToDeg);
    out.set("aligned", r.aligned);
    if (r.aligned)
    {
        MetricsJson& a = out.object("alignment");
        a.set("x_m", r.alignment.x);
        a.set("y_m", r.alignment.y);
        a.set("phi_deg", r.alignment.phi * kRadToDeg);
    }
}

void writeLandmarkMetrics(MetricsJson& out, const LandmarkEvaluator::Result& r)
{
    out.set("association", LandmarkEvaluator::associationName(r.used));
    out.set("matched", r.matches.size());
    out.set("unmatched_estimates", r.unmatched_estimates);
    out.set("unmatched_truth", r.unmatched_truth);
    out.set("mean_error_m", r.mean_error);
    out.set("rmse_m", r.rmse);
    out.set("max_error_m", r.max_error);
    out.set("nees_count", r.nees_count);
    out.set("nees_singular", r.nees_singular);
    out.set("mean_nees", r.mean_nees);
}

void writeRelativePoseMetrics(MetricsJson& out, const RelativePoseError& r)
{
    out.set("pairs", r.pairs);
    out.set("translation_mean_m", r.translation_mean);
    out.set("translation_median_m", r.translation_median);
    out.set("translation_max_m", r.translation_max);
    out.set("rotation_mean_deg", r.rotation_mean * kRadToDeg);
    out.set("rotation_median_deg", r.rotation_median * kRadToDeg);
    out.set("rotation_max_deg", r.rotation_max * kRadToDeg);
}

}  // namespace hymm::eval
