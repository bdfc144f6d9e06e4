// Scan-SLAM on a simulated run against the simulator's truth (ScanSlamStudy.h).
#include "hymm/app/ScanSlamStudy.h"

#include <hymm/dense/outline_metrics.h>
#include <hymm/eval/nees.h>
#include <hymm/scanslam/PointSet.h>
#include <hymm/sim/Simulator.h>
#include <hymm/sim/frame_feed.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <cmath>
#include <ctime>
#include <limits>
#include <map>

namespace hymm::app
{
namespace
{
using scanslam::compose;

Eigen::Vector3d poseError(const Eigen::Vector3d& est, const Eigen::Vector3d& truth)
{
    Eigen::Vector3d e = est - truth;
    e.z() = mrpt::math::wrapToPi(e.z());
    return e;
}

ScanSlamRun::LandmarkErrors landmarkErrors(const denseslam::DenseSlam& slam,
                                           const std::map<long, Eigen::Vector3d>& truth)
{
    ScanSlamRun::LandmarkErrors r;
    double sxy = 0, sphi = 0, snees = 0;
    size_t n_nees = 0;
    for (const auto& [id, x_true] : truth)
    {
        if (!slam.ekf().hasLandmark(id)) continue;
        const Eigen::Vector3d e = poseError(slam.ekf().landmarkBlockMean(id).head<3>(), x_true);
        ++r.landmarks;
        sxy += e.head<2>().squaredNorm();
        sphi += e.z() * e.z();
        const auto v = eval::nees(e, slam.ekf().landmarkBlockCov(id));
        if (v.ok()) snees += v.value, ++n_nees;
    }
    const double n = static_cast<double>(std::max<size_t>(r.landmarks, 1));
    r.rmse_xy_m = std::sqrt(sxy / n);
    r.rmse_phi = std::sqrt(sphi / n);
    r.mean_nees = n_nees ? snees / static_cast<double>(n_nees) : std::nan("");
    return r;
}

double pathRmse(const std::vector<ScanSlamRun::Step>& s, size_t from, size_t to)
{
    double sum = 0;
    for (size_t i = from; i < to; ++i) sum += (s[i].estimate - s[i].truth).head<2>().squaredNorm();
    return to > from ? std::sqrt(sum / static_cast<double>(to - from)) : std::nan("");
}

/** The converged alignments of this frame against the truth (ScanSlamRun::Observation). */
void scoreObservations(const scanslam::ScanLandmarkMap& map, double t, const Eigen::Vector3d& sensor_true,
                       const std::map<long, Eigen::Vector3d>& truth,
                       const std::map<long, Eigen::Vector3d>& made_from, ScanSlamRun& run)
{
    for (const auto& a : map.lastAligned())
    {
        const auto lt = truth.find(a.id);
        if (lt == truth.end()) continue;
        const Eigen::Vector3d z_true = compose(scanslam::inverse(sensor_true), lt->second);
        const Eigen::Vector3d& s0 = made_from.at(a.id);
        ScanSlamRun::Observation o;
        o.t = t;
        o.id = a.id;
        o.sensor = sensor_true.head<2>();
        o.travel_m = (sensor_true - s0).head<2>().norm();
        const Eigen::Vector2d d0 = s0.head<2>() - lt->second.head<2>();
        const Eigen::Vector2d d1 = sensor_true.head<2>() - lt->second.head<2>();
        o.view_change = std::abs(mrpt::math::wrapToPi(std::atan2(d1.y(), d1.x()) - std::atan2(d0.y(), d0.x())));
        o.range_m = d1.norm();
        o.error = poseError(a.z, z_true);
        o.pred_error = poseError(a.z_hat, z_true);
        o.R = a.R;
        o.updated = a.updated;
        o.wide = a.wide;
        run.observations.push_back(o);
    }
}

void scoreTemplates(const denseslam::DenseSlam& slam, const sim::World& world, ScanSlamRun& run)
{
    std::vector<Eigen::Vector2d> pts;
    const auto* src = slam.scanLandmarks();
    if (!src) return;
    for (const auto& [id, tpl] : src->map().templates())
    {
        if (!slam.ekf().hasLandmark(id)) continue;
        const Eigen::Vector3d pose = slam.ekf().landmarkBlockMean(id).head<3>();
        for (const auto& p : tpl.sog.points) pts.push_back(scanslam::transformPoint(pose, p));
    }
    std::vector<dense::Polygon> outlines;
    for (const auto& o : world.objects())
    {
        const auto poly = o.outlineAt(0.0);
        outlines.emplace_back(poly.begin(), poly.end());
    }
    run.template_points = pts.size();
    run.template_outline_mean_m =
        pts.empty() || outlines.empty() ? std::nan("") : dense::evaluateOutlines(pts, outlines).mean_distance_m;
}

// CPU time of this thread: the cost of the step, not the machine's load.
double threadCpuSeconds()
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/** One simulated frame through the pipeline (odometry, then the frame), scored. */
ScanSlamRun::Step processSimFrame(denseslam::DenseSlam& slam, const sim::SimFrame& f)
{
    const double t0 = threadCpuSeconds();
    slam.processOdometry(sim::odometryIncrement(f));
    slam.processFrame(sim::sensoryFrame(f));
    ScanSlamRun::Step s;
    s.seconds = threadCpuSeconds() - t0;
    s.dead_reckoning = f.dr_pose;
    s.t = f.t;
    s.truth = f.true_pose;
    s.estimate = slam.ekf().vehiclePose();
    s.cov = slam.ekf().vehicleCov();
    const auto v = eval::nees(poseError(s.estimate, s.truth), s.cov);
    s.nees = v.ok() ? v.value : std::nan("");
    return s;
}

/** The true frame pose of each scan landmark (where the true sensor saw its template
 *  made) and the loop closure: the first re-observation of a landmark made more than
 *  min_age_s earlier. */
struct ClosureWatch
{
    double min_age_s = 0;
    std::map<long, Eigen::Vector3d> truth;        // landmark id -> true frame pose
    std::map<long, Eigen::Vector3d> made_from;    // id -> true sensor pose at creation
    std::map<long, std::pair<double, int>> seen;  // id -> (creation time, times_seen)
    bool closed = false;

    /** Books the frame's landmarks; true if the frame closes the loop. */
    bool frame(const denseslam::ScanLandmarksSource& src, const ekf::EkfSlam& ekf, const sim::SimFrame& f,
               const Eigen::Vector3d& sensor_true)
    {
        bool closes = false;
        for (const auto& [id, tpl] : src.map().templates())
        {
            const int times = ekf.landmarkBlock(id).times_seen;
            const auto [it, fresh] = seen.try_emplace(id, f.t, times);
            if (fresh)
            {
                truth[id] = compose(sensor_true, tpl.frame_in_sensor);
                made_from[id] = sensor_true;
                continue;
            }
            if (!closed && times > it->second.second && f.t - it->second.first > min_age_s)
                closed = closes = true;
            it->second.second = times;
        }
        return closes;
    }
};

/** Path and landmark scores of the whole run, once its last frame is in. */
void finishRun(ScanSlamRun& run, const denseslam::DenseSlam& slam, const sim::World& world,
               const ClosureWatch& watch, double duration_s)
{
    run.duration_s = duration_s;
    run.after_closure = landmarkErrors(slam, watch.truth);
    if (!watch.closed)
    {
        run.before_closure = run.after_closure;
        run.closure_step = run.steps.size();
    }
    run.path_rmse_before_m = pathRmse(run.steps, 0, run.closure_step);
    run.path_rmse_after_m = pathRmse(run.steps, run.closure_step, run.steps.size());
    run.path_rmse_m = pathRmse(run.steps, 0, run.steps.size());
    double dr = 0;
    for (const auto& s : run.steps) dr += (s.dead_reckoning - s.truth).head<2>().squaredNorm();
    run.dead_reckoning_rmse_m = std::sqrt(dr / static_cast<double>(std::max<size_t>(run.steps.size(), 1)));
    scoreTemplates(slam, world, run);
    run.stats = slam.stats();
    run.counters = slam.scanSourceCounters();
}
}  // namespace

ScanSlamRun runScanSlamStudy(const sim::Scenario& scenario,
                             const mrpt::config::CConfigFileBase& slam_cfg, double closure_min_age_s)
{
    auto slam = denseslam::DenseSlam::fromConfig(slam_cfg);
    sim::Simulator sim(scenario);
    sim::SimFrame f;
    ScanSlamRun run;
    ClosureWatch watch;
    watch.min_age_s = closure_min_age_s;
    Eigen::Vector3d reference_true = Eigen::Vector3d::Zero();  // the scan odometry's reference
    while (sim.next(f))
    {
        // Scores of the state before this frame (the closure is found after it).
        const auto before = watch.closed ? ScanSlamRun::LandmarkErrors{} : landmarkErrors(slam, watch.truth);
        run.steps.push_back(processSimFrame(slam, f));
        // Only a frame with a scan refines the odometry (the last measurement is stale otherwise).
        if (const auto* odo = f.scan ? slam.scanOdometry() : nullptr)
        {
            if (const auto& m = odo->lastRelativeMeasurement())
                run.odometry_alignments.push_back(
                    {poseError(m->mean, compose(scanslam::inverse(reference_true), f.true_pose)), m->cov});
            if (odo->lastScanIsReference()) reference_true = f.true_pose;
        }
        const auto* src = slam.scanLandmarks();
        if (!src || !f.scan) continue;
        const auto& sp = f.scan->sensorPose;
        const Eigen::Vector3d sensor_true = compose(f.true_pose, Eigen::Vector3d(sp.x(), sp.y(), sp.yaw()));
        if (watch.frame(*src, slam.ekf(), f, sensor_true))
        {
            run.closure_t = f.t;
            run.closure_step = run.steps.size() - 1;
            run.before_closure = before;
        }
        scoreObservations(src->map(), f.t, sensor_true, watch.truth, watch.made_from, run);
    }
    finishRun(run, slam, sim.world(), watch, f.t);
    return run;
}

}  // namespace hymm::app
