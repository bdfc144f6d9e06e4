#include "hymm/app/ConsistencyStudy.h"

#include <hymm/app/slam_config.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/app/slam_outputs.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <hymm/eval/nees.h>
#include <hymm/eval/run_metrics.h>
#include <hymm/io/RawlogReader.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/sim/run_scenario.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace hymm::app
{
namespace
{
struct RunOutcome
{
    std::vector<double> vehicle_nees;  //!< per step, NaN where unmatched
    std::vector<double> landmark_nees;  //!< per true landmark, NaN where unmapped
    double final_error = 0, path_rmse = 0, landmark_mean_error = 0;
    bool hll = false;
    double hll_proposed = 0, hll_accepted = 0, hll_initialised = 0, hll_updated = 0;
};

RunOutcome runOne(const sim::Scenario& scenario, const mrpt::config::CConfigFileBase& slam_cfg,
                  const std::string& dir)
{
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw std::runtime_error("cannot create '" + dir + "': " + ec.message());
    sim::runScenario(scenario, dir, false);
    const std::string base = dir + "/" + scenario.run.name;

    DenseSlam slam = DenseSlam::fromConfig(slam_cfg);
    io::RawlogReader reader(base + ".rawlog");
    io::RawlogEntry e;
    while (reader.next(e)) slam.processEntry(e);

    io::GroundTruth gt;
    gt.path = io::readTum(base + "_gt_path.tum");
    gt.landmarks = io::readLandmarksCsv(base + "_gt_landmarks.csv");

    RunOutcome out;
    const std::vector<eval::EstimatedPose> path = estimatedPoses(slam);
    out.vehicle_nees = eval::vehicleNeesSeries(path, gt);

    eval::TrajectoryEvaluator::Options to;
    to.association = eval::TrajectoryEvaluator::Association::Nearest;
    to.time_tolerance = 1e-3;
    const auto traj = eval::TrajectoryEvaluator(to).evaluate(eval::stampedPoses(path), gt.path);
    out.path_rmse = traj.position_rmse;
    out.final_error = traj.errors.empty() ? std::nan("") : traj.errors.back().position();

    eval::LandmarkEvaluator::Options lo;
    lo.association = landmarkAssociationFor(slam);
    const auto lr = eval::LandmarkEvaluator(lo).evaluate(estimatedLandmarks(slam.ekf()), gt.landmarks);
    out.landmark_mean_error = lr.mean_error;
    if (const auto* h = slam.highLevelLandmarks())
    {
        out.hll = true;
        out.hll_proposed = static_cast<double>(h->stats().proposed);
        out.hll_accepted = static_cast<double>(h->stats().accepted);
        out.hll_initialised = static_cast<double>(h->stats().initialised);
        out.hll_updated = static_cast<double>(h->tracker().stats().updated);
    }
    out.landmark_nees.assign(gt.landmarks.size(), std::nan(""));
    for (const auto& m : lr.matches)
        if (m.has_nees && m.nees.ok()) out.landmark_nees[m.truth] = m.nees.value;
    return out;
}

void averageVehicleNees(const std::vector<RunOutcome>& runs, double confidence,
                        ConsistencyStudy::Result& r);
void averageLandmarkNees(const std::vector<RunOutcome>& runs, double confidence,
                         ConsistencyStudy::Result& r);
}  // namespace

ConsistencyStudy::Result ConsistencyStudy::run() const
{
    if (seeds.empty()) throw std::invalid_argument("consistency study: no seeds");
    sim::Scenario scenario = sim::Scenario::fromFile(scenario_ini);
    if (laps > 0)
    {
        scenario.run.laps = laps;
        scenario.run.duration_s = 0;
    }
    const core::StrictConfigFile slam_file(slam_ini);
    loadSlamConfig(slam_file);  // every error before the first run
    const auto* slam_cfg = &slam_file.config();

    std::vector<RunOutcome> runs;
    for (long seed : seeds)
    {
        scenario.run.seed = seed;
        runs.push_back(runOne(scenario, *slam_cfg, work_dir + "/seed_" + std::to_string(seed)));
    }

    Result r;
    r.runs = runs.size();
    r.steps = runs.front().vehicle_nees.size();
    for (const auto& o : runs)
    {
        if (o.vehicle_nees.size() != r.steps)
            throw std::runtime_error("consistency study: runs have different numbers of steps");
        r.final_position_error.push_back(o.final_error);
        r.path_rmse.push_back(o.path_rmse);
        r.landmark_mean_error.push_back(o.landmark_mean_error);
        double sum = 0;
        size_t n = 0;
        for (double v : o.vehicle_nees)
            if (std::isfinite(v)) sum += v, ++n;
        r.vehicle_nees_run_mean.push_back(n ? sum / static_cast<double>(n) : std::nan(""));
        if (o.hll)
        {
            r.hll_proposed.push_back(o.hll_proposed);
            r.hll_accepted.push_back(o.hll_accepted);
            r.hll_initialised.push_back(o.hll_initialised);
            r.hll_updated.push_back(o.hll_updated);
        }
    }

    averageVehicleNees(runs, confidence, r);
    averageLandmarkNees(runs, confidence, r);
    return r;
}

namespace
{
// Vehicle: average over runs at each step (steps unmatched in any run are left out).
void averageVehicleNees(const std::vector<RunOutcome>& runs, double confidence,
                        ConsistencyStudy::Result& r)
{
    const int N = static_cast<int>(r.runs);
    const auto vb = eval::averageNeesBounds(3, N, confidence);
    r.vehicle_band_lower = vb.lower;
    r.vehicle_band_upper = vb.upper;
    r.vehicle_nees.assign(r.steps, std::nan(""));
    double sum = 0;
    size_t counted = 0;
    for (size_t k = 0; k < r.steps; ++k)
    {
        double s = 0;
        bool all = true;
        for (const auto& o : runs)
        {
            if (!std::isfinite(o.vehicle_nees[k])) all = false;
            s += o.vehicle_nees[k];
        }
        if (!all) continue;
        r.vehicle_nees[k] = s / N;
        sum += r.vehicle_nees[k];
        ++counted;
    }
    r.vehicle_nees_mean = counted ? sum / counted : std::nan("");
    r.vehicle_fraction_inside = eval::fractionInsideBounds(r.vehicle_nees, vb);
}

// Landmarks: each true landmark averaged over the runs that mapped it; the band is
// computed for the number of runs that contribute (most landmarks: all of them).
void averageLandmarkNees(const std::vector<RunOutcome>& runs, double confidence,
                         ConsistencyStudy::Result& r)
{
    const int N = static_cast<int>(r.runs);
    const size_t L = runs.front().landmark_nees.size();
    r.landmark_nees.assign(L, std::nan(""));
    size_t inside = 0, tested = 0;
    const auto lb = eval::averageNeesBounds(2, N, confidence);
    r.landmark_band_lower = lb.lower;
    r.landmark_band_upper = lb.upper;
    for (size_t l = 0; l < L; ++l)
    {
        double s = 0;
        int n = 0;
        for (const auto& o : runs)
            if (l < o.landmark_nees.size() && std::isfinite(o.landmark_nees[l])) s += o.landmark_nees[l], ++n;
        if (n == 0) continue;
        r.landmark_nees[l] = s / n;
        const auto b = n == N ? lb : eval::averageNeesBounds(2, n, confidence);
        ++tested;
        if (b.contains(r.landmark_nees[l])) ++inside;
    }
    r.landmark_fraction_inside = tested ? static_cast<double>(inside) / tested : std::nan("");
}
}  // namespace

}  // namespace hymm::app
