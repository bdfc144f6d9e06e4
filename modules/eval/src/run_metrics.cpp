#include "hymm/eval/run_metrics.h"

#include <hymm/eval/TrajectoryEvaluator.h>
#include <hymm/eval/metrics_report.h>
#include <hymm/eval/nees.h>

#include <cmath>

namespace hymm::eval
{
std::vector<io::StampedPose2D> stampedPoses(const std::vector<EstimatedPose>& path)
{
    std::vector<io::StampedPose2D> out;
    out.reserve(path.size());
    for (const auto& s : path) out.push_back({s.t, s.pose[0], s.pose[1], s.pose[2]});
    return out;
}

std::vector<double> vehicleNeesSeries(const std::vector<EstimatedPose>& path,
                                      const io::GroundTruth& gt, double time_tolerance)
{
    std::vector<double> out(path.size(), std::nan(""));
    if (gt.path.empty()) return out;
    TrajectoryEvaluator::Options to;
    to.association = gt.path_has_timestamps ? TrajectoryEvaluator::Association::Nearest
                                            : TrajectoryEvaluator::Association::Index;
    to.time_tolerance = time_tolerance;
    const auto traj = TrajectoryEvaluator(to).evaluate(stampedPoses(path), gt.path);
    // Errors come in the order of the estimates; walk both sequences together.
    size_t i = 0;
    for (const auto& e : traj.errors)
    {
        while (i < path.size() && path[i].t != e.t) ++i;
        if (i == path.size()) break;
        const auto v = nees(Eigen::Vector3d(e.dx, e.dy, e.dphi), path[i].cov);
        if (v.ok()) out[i] = v.value;
        ++i;
    }
    return out;
}

namespace
{
void writePathMetrics(MetricsJson& j, const std::vector<EstimatedPose>& path,
                      const io::GroundTruth& gt)
{
    TrajectoryEvaluator::Options to;
    to.association = gt.path_has_timestamps ? TrajectoryEvaluator::Association::Interpolate
                                            : TrajectoryEvaluator::Association::Index;
    const auto traj = TrajectoryEvaluator(to).evaluate(stampedPoses(path), gt.path);
    writeTrajectoryMetrics(j.object("path"), traj);

    // Vehicle NEES per matched step (3 DOF), against the single-run 95% band.
    const std::vector<double> nees_series = vehicleNeesSeries(path, gt);
    const auto band = averageNeesBounds(3, 1, 0.95);
    double sum = 0;
    size_t n = 0;
    for (double v : nees_series)
        if (std::isfinite(v)) sum += v, ++n;
    auto& nj = j.object("vehicle_nees");
    nj.set("mean", n ? sum / n : std::nan(""));
    nj.set("steps", static_cast<unsigned long>(n));
    nj.set("band_lower", band.lower);
    nj.set("band_upper", band.upper);
    nj.set("fraction_inside_band", fractionInsideBounds(nees_series, band));
}

void writeLandmarkAndNeesMetrics(MetricsJson& j, const std::vector<LandmarkEstimate>& landmarks,
                                 LandmarkEvaluator::Association association, const io::GroundTruth& gt)
{
    LandmarkEvaluator::Options lo;
    lo.association = association;
    const auto lr = LandmarkEvaluator(lo).evaluate(landmarks, gt.landmarks);
    eval::writeLandmarkMetrics(j.object("landmarks"), lr);
    std::vector<double> lm_nees;
    for (const auto& m : lr.matches)
        if (m.has_nees && m.nees.ok()) lm_nees.push_back(m.nees.value);
    const auto band = averageNeesBounds(2, 1, 0.95);
    auto& lj = j.object("landmark_nees");
    lj.set("band_lower", band.lower);
    lj.set("band_upper", band.upper);
    lj.set("fraction_inside_band", fractionInsideBounds(lm_nees, band));
}
}  // namespace

void writeRunMetrics(MetricsJson& j, const std::vector<EstimatedPose>& path,
                     const std::vector<LandmarkEstimate>& landmarks,
                     LandmarkEvaluator::Association association, const io::GroundTruth& gt)
{
    if (!gt.path.empty()) writePathMetrics(j, path, gt);
    if (!gt.landmarks.empty()) writeLandmarkAndNeesMetrics(j, landmarks, association, gt);
}

MetricsJson evaluateResultFiles(const std::string& path_tum, const std::string& landmarks_csv,
                                const io::GroundTruth& gt)
{
    MetricsJson j;
    if (!path_tum.empty() && !gt.path.empty())
    {
        TrajectoryEvaluator::Options to;
        to.association = gt.path_has_timestamps ? TrajectoryEvaluator::Association::Interpolate
                                                : TrajectoryEvaluator::Association::Index;
        const auto traj = TrajectoryEvaluator(to).evaluate(io::readTum(path_tum), gt.path);
        writeTrajectoryMetrics(j.object("path"), traj);
    }
    if (!landmarks_csv.empty() && !gt.landmarks.empty())
    {
        const auto recs = io::readLandmarksCsv(landmarks_csv);
        const bool has_cov = !recs.empty() && recs.front().extra.size() >= 3;
        const auto est = landmarkEstimatesFromRecords(recs, has_cov ? 0 : -1);
        const auto lr = LandmarkEvaluator(LandmarkEvaluator::Options{}).evaluate(est, gt.landmarks);
        eval::writeLandmarkMetrics(j.object("landmarks"), lr);
    }
    return j;
}

}  // namespace hymm::eval
