/**
 * @file delayed_store_eval.cpp
 * @brief hymm-delayed-store-eval: the delayed dense store (thesis Sec. 3.7.3) on a
 *        single-pass simulated run, with the store off and on.
 *
 *   hymm-delayed-store-eval --scenario configs/sim/ch3_single_pass.ini
 *       --slam configs/ch3_single_pass_slam.ini --out DIR [--figures DIR] [--seed N]
 *       [--figure-prefix P] [--duration S] [--known-ids]
 *
 * Simulates the scenario in memory and feeds its frames (odometry increment with its
 * covariance, laser scan, landmark readings: what its rawlog carries) to DenseSlam twice
 * ([DelayedDenseStore] enabled = false, then true; everything else from --slam), then
 * reports, against the simulator's ground truth:
 *  - the part of the object outlines the laser saw (eval::laserSeenOutline: scans at the
 *    true poses, samples every 0.05 m with a return within 0.3 m) and how much of it each
 *    dense point map covers (a point within 0.3 m);
 *  - mean and p95 distance of the points to the true surfaces (outlines and trunks), of
 *    all points and of the points fused from the store alone;
 *  - returns stored, fused, still waiting and dropped by the store.
 * Each map is scored three times: as rendered (regions on their estimated vertices, so the
 * points carry the feature map's drift, which the store cannot change); as rendered,
 * aligned (the same points after the least-squares SE(2) fit, eval::alignSE2, of the
 * estimated real landmarks onto their true positions, paired as the landmark frame pairs
 * them and virtual landmarks left out: one rigid transform for the whole map, which
 * removes the common rigid error of the feature map but not its shape); and in the
 * landmark frame (eval::pointsAtTrueVertices: regions on the true vertex positions, so
 * the points carry only their error relative to the landmarks). The landmark errors
 * before and after the fit are reported by where along the true path each landmark was
 * first detected, per 20 m, with the rotation a fit of that stretch alone needs (a map
 * that is bent, not just rotated, needs different ones) and the vehicle's heading error
 * there. The feature map and the
 * path are the same bit for bit with and without the store (UIF), so the regions and
 * every directly inserted point are too: the points of the "on" map that the "off" map
 * lacks are exactly the fused ones (checked against the pipeline's count).
 * Writes DIR/result.json and, with --figures, P_store_off.png and P_store_on.png
 * (landmark frame; P = single_pass unless --figure-prefix). Exit code 0 if, in the
 * landmark frame, the store maps >= 95 % of the seen outline and more than without it;
 * 2 if not; 1 on error.
 */
#include <hymm/core/command_line.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/app/slam_outputs.h>
#include <hymm/eval/LandmarkEvaluator.h>
#include <hymm/eval/MetricsJson.h>
#include <hymm/eval/laser_coverage.h>
#include <hymm/eval/se2_alignment.h>
#include <hymm/sim/Simulator.h>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPoint2D.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/system/filesystem.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "single_pass_figure.h"

namespace
{
using hymm::denseslam::DenseSlam;
using V2 = Eigen::Vector2d;

constexpr double kRequiredSeenCoverage = 0.95;  //!< the store must map this much of what was seen
constexpr int kTrunkSides = 32;                 //!< polygon of a trunk circle (0.5 % of r)
constexpr double kStretchM = 20;                //!< [m] of true path per row of the drift table
constexpr double kStampTolerance = 1e-6;        //!< [s] estimated and true path samples match
constexpr double kDetectionGate = 2.0;          //!< [m] detection (at the true pose) to landmark

/** Everything the runs are scored against. */
struct Truth
{
    std::vector<hymm::io::StampedPose2D> path;
    std::vector<hymm::io::LandmarkRecord> landmarks;
    std::vector<hymm::dense::Polygon> outlines;
    std::vector<std::string> names;              //!< per outline
    std::vector<hymm::dense::Polygon> surfaces;  //!< outlines + trunk circles
    std::vector<hymm::eval::TimedScan> scans;
    /** Per landmark: length of the true path [m] when a detection first fell within
     *  kDetectionGate of it (NaN if never), where the filter first met it. */
    std::vector<double> first_detected;
};

/** One point map scored against the truth. */
struct MapScore
{
    std::vector<V2> points, fused;
    hymm::eval::SeenCoverage coverage;
    hymm::dense::OutlineMetrics accuracy, fused_accuracy;
    size_t seen_in_regions = 0;   //!< seen samples inside a final region (drawn in this frame)
    std::vector<char> in_region;  //!< per outline sample: inside a final region
    std::vector<hymm::ltr::TriangleFrame::Vertices> triangles;
};

/** One real landmark of the filter paired with its true position. */
struct LandmarkError
{
    long id = 0;
    V2 estimate, truth;
    double along_path = 0;  //!< [m] length of the true path when first detected (NaN: never)
    double error = 0;       //!< [m] |estimate - truth|
    double aligned = 0;     //!< [m] after the map's SE(2) fit
};

/** The least-squares SE(2) fit of the estimated real landmarks onto the true ones. */
struct LandmarkAlignment
{
    hymm::eval::Se2Transform transform;
    std::vector<LandmarkError> landmarks;
    double mean_error = 0, max_error = 0, mean_aligned = 0, max_aligned = 0;  //!< [m]
};

/** One DenseSlam run. */
struct ModeResult
{
    bool store = false;
    DenseSlam::Stats stats;
    size_t waiting = 0;  //!< returns still in the store at the end
    MapScore global, aligned, local;
    LandmarkAlignment alignment;
    std::vector<double> heading_error;  //!< [rad] filter - truth per true path sample
    size_t regions_skipped = 0;         //!< regions not drawn in the landmark frame
};

std::string readFile(const std::string& path)
{
    std::ifstream f(path);
    if (!f) throw std::runtime_error("cannot read '" + path + "'");
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

/** One sensory frame as the pipeline receives it. */
struct Frame
{
    mrpt::poses::CPosePDFGaussian odometry;
    mrpt::obs::CSensoryFrame observations;
};

/** Records where along the true path each landmark was first detected: every reading
 *  placed from the true pose, given to the nearest true landmark within kDetectionGate
 *  (no reported ids needed). */
void markDetected(const mrpt::obs::CObservationBearingRange& obs, const Eigen::Vector3d& pose,
                  double along, Truth& t)
{
    const mrpt::poses::CPose2D sensor = mrpt::poses::CPose2D(pose[0], pose[1], pose[2]) +
                                        mrpt::poses::CPose2D(obs.sensorLocationOnRobot);
    for (const auto& m : obs.sensedData)
    {
        const auto p =
            sensor + mrpt::poses::CPoint2D(m.range * std::cos(m.yaw), m.range * std::sin(m.yaw));
        size_t best = t.landmarks.size();
        double best_d = kDetectionGate;
        for (size_t k = 0; k < t.landmarks.size(); ++k)
            if (const double d = std::hypot(t.landmarks[k].x - p.x(), t.landmarks[k].y - p.y());
                d <= best_d)
                best_d = d, best = k;
        if (best < t.landmarks.size() && std::isnan(t.first_detected[best]))
            t.first_detected[best] = along;
    }
}

/** Runs the scenario in memory: the frames for the pipeline and the ground truth. The
 *  pipeline gets exactly what the rawlog would carry (odometry increment with its
 *  covariance, the laser scan, the landmark readings), without a file in between. */
std::vector<Frame> simulate(const hymm::sim::Scenario& scenario, Truth& t)
{
    hymm::sim::Simulator sim(scenario);
    for (const auto& l : sim.world().landmarks())
        t.landmarks.push_back({l.id, l.position.x(), l.position.y(), {l.radius}});
    t.first_detected.assign(t.landmarks.size(), std::nan(""));
    std::vector<Frame> frames;
    hymm::sim::SimFrame f;
    double along = 0;
    while (sim.next(f))
    {
        if (!t.path.empty())
            along += std::hypot(f.true_pose[0] - t.path.back().x, f.true_pose[1] - t.path.back().y);
        if (f.detections) markDetected(*f.detections, f.true_pose, along, t);
        Frame fr;
        fr.odometry = mrpt::poses::CPosePDFGaussian(
            mrpt::poses::CPose2D(f.odometry_mean[0], f.odometry_mean[1], f.odometry_mean[2]),
            mrpt::math::CMatrixDouble33(f.odometry_cov));
        if (f.scan) fr.observations.insert(f.scan);
        if (f.detections) fr.observations.insert(f.detections);
        frames.push_back(std::move(fr));
        const double stamp = mrpt::Clock::toDouble(f.stamp);
        t.path.push_back({stamp, f.true_pose[0], f.true_pose[1], f.true_pose[2]});
        if (f.scan) t.scans.push_back({stamp, hymm::dense::ScanPoints::fromRangeScan(*f.scan)});
    }
    for (const auto& o : sim.world().objects())
    {
        if (!o.isStatic())
            throw std::runtime_error("object '" + o.name +
                                     "' moves or appears: the evaluation needs a static world");
        const auto outline = o.outlineAt(0);
        t.outlines.emplace_back(outline.begin(), outline.end());
        t.names.push_back(o.name);
    }
    t.surfaces = t.outlines;
    for (const auto& tr : hymm::app::trueTrunks(t.landmarks))
        t.surfaces.push_back(hymm::dense::circlePolygon(tr.centre, tr.radius, kTrunkSides));
    return frames;
}

/**
 * a minus b as multisets of points equal in single precision. The points layer stores
 * floats, and the passive states (virtual apexes) are not bitwise the same with and
 * without the store's passive blocks (the filter updates all passive rows together),
 * so regions drawn on them differ in the last bits of a double.
 */
std::vector<V2> difference(const std::vector<V2>& a, const std::vector<V2>& b)
{
    using F2 = std::pair<float, float>;
    const auto key = [](const V2& p)
    { return F2(static_cast<float>(p.x()), static_cast<float>(p.y())); };
    std::map<F2, size_t> in_b;
    for (const V2& p : b) ++in_b[key(p)];
    std::vector<V2> out;
    for (const V2& p : a)
    {
        const auto it = in_b.find(key(p));
        if (it != in_b.end() && it->second > 0)
            --it->second;
        else
            out.push_back(p);
    }
    return out;
}

/** True position of every filter landmark the evaluation can associate with the truth. */
std::map<long, V2> associatedTruth(const DenseSlam& slam, const Truth& truth)
{
    hymm::eval::LandmarkEvaluator::Options o;
    o.association = hymm::app::landmarkAssociationFor(slam);
    const auto est = hymm::app::estimatedLandmarks(slam.ekf());
    std::map<long, V2> out;
    for (const auto& m : hymm::eval::LandmarkEvaluator(o).evaluate(est, truth.landmarks).matches)
        out[est[m.estimate].id] = V2(truth.landmarks[m.truth].x, truth.landmarks[m.truth].y);
    return out;
}

/** Cumulative length of the true path at each of its samples. */
std::vector<double> arcLength(const Truth& t)
{
    std::vector<double> s(t.path.size(), 0.0);
    for (size_t i = 1; i < t.path.size(); ++i)
        s[i] = s[i - 1] + std::hypot(t.path[i].x - t.path[i - 1].x, t.path[i].y - t.path[i - 1].y);
    return s;
}

/** The SE(2) fit of the filter's real landmarks (`truth_of`: filter id -> true position;
 *  virtual landmarks, which stand on an edge rather than on a true landmark, left out). */
LandmarkAlignment alignLandmarks(const DenseSlam& slam, const std::map<long, V2>& truth_of,
                                 const Truth& truth)
{
    LandmarkAlignment a;
    std::vector<V2> est, tru;
    for (const auto& [id, p] : truth_of)
    {
        if (slam.virtualLandmarkIds().count(id)) continue;
        LandmarkError e;
        e.id = id;
        e.estimate = slam.ekf().landmarkMean(id);
        e.truth = p;
        // truth_of holds the true positions themselves: the landmark at distance 0.
        double best = std::numeric_limits<double>::infinity();
        for (size_t k = 0; k < truth.landmarks.size(); ++k)
            if (const double d =
                    std::hypot(truth.landmarks[k].x - p.x(), truth.landmarks[k].y - p.y());
                d < best)
                best = d, e.along_path = truth.first_detected[k];
        a.landmarks.push_back(e);
        est.push_back(e.estimate);
        tru.push_back(e.truth);
    }
    const auto t = hymm::eval::alignSE2(est, tru);
    if (!t || est.size() < 3)
        throw std::runtime_error(
            "cannot align the feature map with the truth: " + std::to_string(est.size()) +
            " real landmarks associated with the truth (at least 3 needed)");
    a.transform = *t;
    for (auto& e : a.landmarks)
    {
        e.error = (e.estimate - e.truth).norm();
        e.aligned = (t->apply(e.estimate) - e.truth).norm();
        a.mean_error += e.error;
        a.mean_aligned += e.aligned;
        a.max_error = std::max(a.max_error, e.error);
        a.max_aligned = std::max(a.max_aligned, e.aligned);
    }
    a.mean_error /= static_cast<double>(a.landmarks.size());
    a.mean_aligned /= static_cast<double>(a.landmarks.size());
    return a;
}

/** The filter's heading error at every true path sample with an estimate of the same stamp. */
std::vector<double> headingErrors(const DenseSlam& slam, const Truth& truth)
{
    std::vector<double> out(truth.path.size(), std::nan(""));
    size_t j = 0;
    for (const auto& p : slam.path())
    {
        while (j < truth.path.size() && truth.path[j].t < p.t - kStampTolerance) ++j;
        if (j == truth.path.size()) break;
        if (std::abs(truth.path[j].t - p.t) <= kStampTolerance)
            out[j] = mrpt::math::wrapToPi(p.pose.z() - truth.path[j].phi);
    }
    return out;
}

void score(MapScore& m, const std::vector<V2>* baseline, const Truth& truth,
           const hymm::eval::SeenOutline& seen)
{
    if (baseline) m.fused = difference(m.points, *baseline);
    m.coverage = hymm::eval::coverageOfSeen(seen, m.points);
    m.accuracy = hymm::dense::evaluateOutlines(m.points, truth.surfaces);
    m.fused_accuracy = hymm::dense::evaluateOutlines(m.fused, truth.surfaces);
    std::vector<hymm::ltr::TriangleFrame> frames;
    for (const auto& v : m.triangles)
        if (auto f = hymm::ltr::TriangleFrame::tryCreate(v)) frames.push_back(*f);
    m.in_region.resize(seen.samples.points.size(), 0);
    for (size_t i = 0; i < seen.samples.points.size(); ++i)
    {
        m.in_region[i] = std::any_of(frames.begin(), frames.end(),
                                     [&](const hymm::ltr::TriangleFrame& f)
                                     { return f.contains(seen.samples.points[i]); });
        m.seen_in_regions += seen.seen[i] && m.in_region[i];
    }
}

ModeResult runMode(const std::string& slam_ini, bool store, const std::vector<Frame>& frames,
                   const Truth& truth, const hymm::eval::SeenOutline& seen,
                   const ModeResult* baseline)
{
    mrpt::config::CConfigFileMemory cfg(slam_ini);
    cfg.write("DelayedDenseStore", "enabled", store);
    auto slam = DenseSlam::fromConfig(cfg);
    if (!slam.hybridMap() || !slam.hybridMap()->options().enable_points)
        throw std::runtime_error(
            "the --slam configuration must enable the points layer ([DenseSlam] dense_layers)");
    for (const Frame& f : frames)
    {
        slam.processOdometry(f.odometry);
        slam.processFrame(f.observations);
    }
    slam.refreshRegions();  // render at the final landmark estimates

    ModeResult r;
    r.store = store;
    r.stats = slam.stats();
    r.waiting = slam.delayedStore() ? slam.delayedStore()->numStoredPoints() : 0;
    const auto& part = *slam.partition();
    // As rendered.
    mrpt::maps::CSimplePointsMap pts;
    slam.hybridMap()->renderPoints(part, pts);
    r.global.points = hymm::dense::pointsOf(pts);
    for (long id : part.regionIds()) r.global.triangles.push_back(part.region(id).current);
    score(r.global, baseline ? &baseline->global.points : nullptr, truth, seen);
    const auto truth_of = associatedTruth(slam, truth);
    // As rendered, aligned: one rigid transform for the whole map.
    r.alignment = alignLandmarks(slam, truth_of, truth);
    const auto& tf = r.alignment.transform;
    for (const V2& p : r.global.points) r.aligned.points.push_back(tf.apply(p));
    for (auto v : r.global.triangles)
    {
        for (auto& p : v) p = tf.apply(p);
        r.aligned.triangles.push_back(v);
    }
    score(r.aligned, baseline ? &baseline->aligned.points : nullptr, truth, seen);
    r.heading_error = headingErrors(slam, truth);
    // In the landmark frame.
    const auto vertices = hymm::eval::trueRegionVertices(part, truth_of);
    const auto lf = hymm::eval::pointsAtTrueVertices(*slam.hybridMap(), part, vertices);
    r.local.points = lf.points;
    r.regions_skipped = lf.regions_skipped;
    for (long id : part.regionIds())
    {
        hymm::ltr::TriangleFrame::Vertices v;
        bool known = true;
        for (size_t k = 0; k < 3; ++k)
        {
            const auto it = vertices.find(part.region(id).vertex_ids[k]);
            known = known && it != vertices.end();
            if (known) v[k] = it->second;
        }
        if (known) r.local.triangles.push_back(v);
    }
    score(r.local, baseline ? &baseline->local.points : nullptr, truth, seen);
    return r;
}

void saveFigure(const ModeResult& r, const Truth& truth, const hymm::eval::SeenOutline& seen,
                const std::string& path)
{
    hymm::bench::SinglePassFigure f;
    f.title = std::string("single pass, delayed dense store ") + (r.store ? "ON" : "OFF") + ": " +
              std::to_string(static_cast<int>(std::lround(100 * r.local.coverage.seen_coverage))) +
              " % of the seen outline mapped (regions drawn on the true landmarks)";
    for (size_t o = 0; o < truth.outlines.size(); ++o)
    {
        bool any = false;
        for (size_t i = 0; i < seen.samples.points.size() && !any; ++i)
            any = seen.samples.outline[i] == o && seen.seen[i];
        if (any) f.outlines.push_back(truth.outlines[o]);
    }
    for (const auto& p : truth.path) f.true_path.emplace_back(p.x, p.y);
    f.fused_points = r.local.fused;
    f.direct_points = difference(r.local.points, r.local.fused);
    for (size_t i = 0; i < seen.samples.points.size(); ++i)
        if (seen.seen[i] && !r.local.coverage.covered[i]) f.holes.push_back(seen.samples.points[i]);
    f.triangles = r.local.triangles;
    f.save(path);
}

void writeScore(hymm::eval::MetricsJson& j, const MapScore& m, bool store)
{
    j.set("points", static_cast<unsigned long>(m.points.size()));
    j.set("seen_coverage", m.coverage.seen_coverage);
    j.set("coverage", m.coverage.coverage);
    j.set("seen_samples_in_final_regions", static_cast<unsigned long>(m.seen_in_regions));
    j.set("mean_distance_m", m.accuracy.mean_distance_m);
    j.set("p95_distance_m", m.accuracy.p95_distance_m);
    if (!store) return;
    j.set("fused_points", static_cast<unsigned long>(m.fused.size()));
    j.set("fused_mean_distance_m", m.fused_accuracy.mean_distance_m);
    j.set("fused_p95_distance_m", m.fused_accuracy.p95_distance_m);
}

void writeMode(hymm::eval::MetricsJson& j, const ModeResult& r)
{
    writeScore(j.object("rendered"), r.global, r.store);
    writeScore(j.object("rendered_aligned"), r.aligned, r.store);
    writeScore(j.object("landmark_frame"), r.local, r.store);
    const auto& a = r.alignment;
    auto& aj = j.object("landmark_alignment");
    aj.set("landmarks", static_cast<unsigned long>(a.landmarks.size()));
    aj.set("x", a.transform.x);
    aj.set("y", a.transform.y);
    aj.set("phi_deg", a.transform.phi * 180.0 / M_PI);
    aj.set("landmark_mean_error_m", a.mean_error);
    aj.set("landmark_max_error_m", a.max_error);
    aj.set("landmark_mean_error_aligned_m", a.mean_aligned);
    aj.set("landmark_max_error_aligned_m", a.max_aligned);
    j.set("regions", static_cast<unsigned long>(r.stats.regions_created - r.stats.regions_removed));
    j.set("regions_not_drawn_in_landmark_frame", static_cast<unsigned long>(r.regions_skipped));
    j.set("returns_in_regions", static_cast<unsigned long>(r.stats.returns_stored));
    j.set("returns_outside_regions", static_cast<unsigned long>(r.stats.returns_outside));
    if (!r.store) return;
    auto& s = j.object("store");
    s.set("stored", static_cast<unsigned long>(r.stats.delayed_stored));
    s.set("fused", static_cast<unsigned long>(r.stats.delayed_fused));
    s.set("waiting_at_end", static_cast<unsigned long>(r.waiting));
    s.set("dropped",
          static_cast<unsigned long>(r.stats.delayed_stored - r.stats.delayed_fused - r.waiting));
    s.set("not_stored",
          static_cast<unsigned long>(r.stats.returns_outside - r.stats.delayed_stored));
}

std::string meanP95(const hymm::dense::OutlineMetrics& m)
{
    if (!m.points) return "-";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3f / %.3f", m.mean_distance_m, m.p95_distance_m);
    return buf;
}

void printTable(const hymm::eval::SeenOutline& seen, const ModeResult& off, const ModeResult& on,
                const Truth& truth)
{
    const auto pc = [](double v) { return 100.0 * v; };
    const auto of = [&](size_t k)
    { return pc(static_cast<double>(k) / std::max<size_t>(1, seen.seen_samples)); };
    const auto sensor_only = hymm::dense::evaluateOutlines(seen.returns.points, truth.surfaces);
    std::printf(
        "outline samples %zu, seen by the laser %zu (%.1f %%); scans placed %zu, unmatched %zu; "
        "returns at the true poses: mean / p95 distance to the surfaces %s m (sensor noise "
        "alone)\n\n",
        seen.samples.points.size(), seen.seen_samples, pc(seen.seenFraction()),
        seen.returns.scans_placed, seen.returns.scans_unmatched, meanP95(sensor_only).c_str());
    std::printf(
        "| map | store | points | seen outline mapped | whole outline mapped | mean / p95 dist. "
        "all [m] | "
        "fused points | mean / p95 dist. fused [m] | seen outline in a final region |\n"
        "|---|---|---|---|---|---|---|---|---|\n");
    const std::pair<const char*, MapScore ModeResult::*> maps[] = {
        {"landmark frame", &ModeResult::local},
        {"as rendered", &ModeResult::global},
        {"as rendered, aligned", &ModeResult::aligned}};
    for (const auto& [name, member] : maps)
        for (const ModeResult* r : {&off, &on})
        {
            const MapScore& m = r->*member;
            std::printf("| %s | %s | %zu | %.1f %% | %.1f %% | %s | %zu | %s | %.1f %% |\n", name,
                        r->store ? "on" : "off", m.points.size(), pc(m.coverage.seen_coverage),
                        pc(m.coverage.coverage), meanP95(m.accuracy).c_str(), m.fused.size(),
                        meanP95(m.fused_accuracy).c_str(), of(m.seen_in_regions));
        }
    const auto& s = on.stats;
    std::printf(
        "\nreturns in no region when seen %zu: stored %zu (fused %zu, waiting at the end %zu, "
        "dropped %zu), "
        "not stored %zu; regions %zu (on virtual apexes %zu, apexes rejected %zu; not drawn in the "
        "landmark frame: %zu)\n",
        s.returns_outside, s.delayed_stored, s.delayed_fused, on.waiting,
        s.delayed_stored - s.delayed_fused - on.waiting, s.returns_outside - s.delayed_stored,
        s.regions_created - s.regions_removed, s.virtual_landmarks, s.virtual_rejected,
        on.regions_skipped);
    size_t reach = 0, reach_off = 0, reach_on = 0;
    for (size_t i = 0; i < seen.samples.points.size(); ++i)
        if (seen.seen[i] && on.local.in_region[i])
        {
            ++reach;
            reach_off += off.local.coverage.covered[i];
            reach_on += on.local.coverage.covered[i];
        }
    std::printf(
        "landmark frame, seen outline inside a final region (what any store could map): %zu "
        "samples, "
        "mapped off %.1f %%, on %.1f %%\n",
        reach, pc(static_cast<double>(reach_off) / std::max<size_t>(1, reach)),
        pc(static_cast<double>(reach_on) / std::max<size_t>(1, reach)));
    std::printf(
        "\nlandmark frame, per object (mapped and in a region: fractions of the seen samples):\n\n"
        "| object | seen | in a final region | mapped off | mapped on |\n|---|---|---|---|---|\n");
    for (size_t o = 0; o < truth.outlines.size(); ++o)
    {
        size_t n = 0, v = 0, c_off = 0, c_on = 0, in = 0;
        for (size_t i = 0; i < seen.samples.points.size(); ++i)
        {
            if (seen.samples.outline[i] != o) continue;
            ++n;
            if (!seen.seen[i]) continue;
            ++v;
            c_off += off.local.coverage.covered[i];
            c_on += on.local.coverage.covered[i];
            in += on.local.in_region[i];
        }
        if (!v) continue;
        const auto frac = [&](size_t k)
        { return pc(static_cast<double>(k) / static_cast<double>(v)); };
        std::printf("| %s | %.0f %% | %.0f %% | %.0f %% | %.0f %% |\n", truth.names[o].c_str(),
                    pc(static_cast<double>(v) / static_cast<double>(n)), frac(in), frac(c_off),
                    frac(c_on));
    }
}
/** Landmark errors and the vehicle's heading error over one stretch of the true path. */
struct Stretch
{
    double from = 0;  //!< [m] along the true path
    size_t landmarks = 0;
    double mean_error = 0, max_error = 0, mean_aligned = 0, max_aligned = 0;  //!< [m]
    double local_phi = std::nan("");       //!< [rad] rotation of a fit of this stretch alone
    double local_residual = std::nan("");  //!< [m] mean landmark error after that fit
    double heading_error = std::nan("");   //!< [rad] mean |filter - truth| of the vehicle
};

std::vector<Stretch> stretches(const ModeResult& r, const Truth& truth)
{
    const auto s = arcLength(truth);
    const double length = s.empty() ? 0.0 : s.back();
    std::vector<Stretch> out(static_cast<size_t>(std::floor(length / kStretchM)) + 1);
    std::vector<std::vector<V2>> est(out.size()), tru(out.size());
    const auto bin = [&](double along)
    { return std::min(out.size() - 1, static_cast<size_t>(std::max(0.0, along) / kStretchM)); };
    for (size_t k = 0; k < out.size(); ++k) out[k].from = kStretchM * static_cast<double>(k);
    for (const auto& e : r.alignment.landmarks)
    {
        if (std::isnan(e.along_path)) continue;  // paired with a true landmark never detected
        Stretch& b = out[bin(e.along_path)];
        ++b.landmarks;
        b.mean_error += e.error;
        b.mean_aligned += e.aligned;
        b.max_error = std::max(b.max_error, e.error);
        b.max_aligned = std::max(b.max_aligned, e.aligned);
        est[bin(e.along_path)].push_back(e.estimate);
        tru[bin(e.along_path)].push_back(e.truth);
    }
    std::vector<double> heading_sum(out.size(), 0.0);
    std::vector<size_t> heading_n(out.size(), 0);
    for (size_t i = 0; i < s.size(); ++i)
        if (!std::isnan(r.heading_error[i]))
        {
            heading_sum[bin(s[i])] += std::abs(r.heading_error[i]);
            ++heading_n[bin(s[i])];
        }
    for (size_t k = 0; k < out.size(); ++k)
    {
        Stretch& b = out[k];
        if (heading_n[k]) b.heading_error = heading_sum[k] / static_cast<double>(heading_n[k]);
        if (!b.landmarks) continue;
        b.mean_error /= static_cast<double>(b.landmarks);
        b.mean_aligned /= static_cast<double>(b.landmarks);
        if (est[k].size() < 3) continue;
        if (const auto t = hymm::eval::alignSE2(est[k], tru[k]))
        {
            b.local_phi = t->phi;
            double sum = 0;
            for (size_t i = 0; i < est[k].size(); ++i)
                sum += (t->apply(est[k][i]) - tru[k][i]).norm();
            b.local_residual = sum / static_cast<double>(est[k].size());
        }
    }
    return out;
}

void printAlignment(const ModeResult& off, const ModeResult& on, const Truth& truth)
{
    const auto deg = [](double rad) { return rad * 180.0 / M_PI; };
    const auto& a = on.alignment;
    const auto &t = a.transform, &t_off = off.alignment.transform;
    const bool same = t.x == t_off.x && t.y == t_off.y && t.phi == t_off.phi;
    std::printf(
        "\nalignment of the feature map (%zu real landmarks, paired by %s): x %.3f m, y %.3f m, "
        "phi %.3f deg (store off: %s); landmark error mean / max %.3f / %.3f m before the fit, "
        "%.3f / %.3f m after (store off: %.3f / %.3f m before, %.3f / %.3f m after)\n",
        a.landmarks.size(), on.stats.observations_with_id > 0 ? "id" : "nearest true landmark", t.x,
        t.y, deg(t.phi), same ? "the same transform" : "a different transform", a.mean_error,
        a.max_error, a.mean_aligned, a.max_aligned, off.alignment.mean_error,
        off.alignment.max_error, off.alignment.mean_aligned, off.alignment.max_aligned);
    std::printf(
        "\nlandmark errors by where along the true path the landmark was first detected, and the "
        "vehicle's heading error there (store on; a fit of a stretch alone "
        "rotates by the same angle as the whole map's fit if the map is only rotated, by "
        "different ones if it is bent):\n\n"
        "| along the path [m] | landmarks | error mean / max [m] | after the map's fit mean / max "
        "[m] | fit of the stretch alone: phi [deg], mean error [m] | vehicle heading error, mean "
        "abs [deg] |\n|---|---|---|---|---|---|\n");
    for (const Stretch& b : stretches(on, truth))
    {
        char local[64] = "-";
        if (!std::isnan(b.local_phi))
            std::snprintf(local, sizeof local, "%.2f, %.3f", deg(b.local_phi), b.local_residual);
        if (b.landmarks)
            std::printf("| %.0f-%.0f | %zu | %.3f / %.3f | %.3f / %.3f | %s | %.2f |\n", b.from,
                        b.from + kStretchM, b.landmarks, b.mean_error, b.max_error, b.mean_aligned,
                        b.max_aligned, local, deg(b.heading_error));
        else
            std::printf("| %.0f-%.0f | 0 | - | - | - | %.2f |\n", b.from, b.from + kStretchM,
                        deg(b.heading_error));
    }
}

void writeStretches(hymm::eval::MetricsJson& j, const ModeResult& r, const Truth& truth)
{
    std::vector<double> from, n, mean, max, mean_al, max_al, phi, resid, heading;
    for (const Stretch& b : stretches(r, truth))
    {
        from.push_back(b.from);
        n.push_back(static_cast<double>(b.landmarks));
        const double none = std::nan("");
        mean.push_back(b.landmarks ? b.mean_error : none);
        max.push_back(b.landmarks ? b.max_error : none);
        mean_al.push_back(b.landmarks ? b.mean_aligned : none);
        max_al.push_back(b.landmarks ? b.max_aligned : none);
        phi.push_back(b.local_phi * 180.0 / M_PI);
        resid.push_back(b.local_residual);
        heading.push_back(b.heading_error * 180.0 / M_PI);
    }
    j.set("stretch_m", kStretchM);
    j.set("from_m", from);
    j.set("landmarks", n);
    j.set("mean_error_m", mean);
    j.set("max_error_m", max);
    j.set("mean_error_aligned_m", mean_al);
    j.set("max_error_aligned_m", max_al);
    j.set("stretch_fit_phi_deg", phi);
    j.set("stretch_fit_mean_error_m", resid);
    j.set("vehicle_mean_abs_heading_error_deg", heading);
}
}  // namespace

int main(int argc, char** argv)
{
    try
    {
        TCLAP::CmdLine cmd(
            "hymm-delayed-store-eval: delayed dense store on a single-pass simulated run", ' ',
            "0.1");
        TCLAP::ValueArg<std::string> sc("", "scenario", "simulator scenario .ini", true, "", "FILE",
                                        cmd);
        TCLAP::ValueArg<std::string> sl("", "slam", "pipeline .ini (points layer on)", true, "",
                                        "FILE", cmd);
        TCLAP::ValueArg<std::string> out("", "out", "output folder", true, "", "DIR", cmd);
        TCLAP::ValueArg<std::string> fig("", "figures", "folder for the two PNGs", false, "", "DIR",
                                         cmd);
        TCLAP::ValueArg<std::string> prefix("", "figure-prefix",
                                            "PNG names: PREFIX_store_off.png, PREFIX_store_on.png",
                                            false, "single_pass", "PREFIX", cmd);
        TCLAP::ValueArg<long> seed("", "seed", "noise seed (overrides the scenario's)", false, 0,
                                   "N", cmd);
        TCLAP::ValueArg<double> duration(
            "", "duration", "run length [s] (overrides [Scenario] duration_s)", false, 0, "S", cmd);
        TCLAP::SwitchArg ids("", "known-ids",
                             "the landmark detector reports the true ids (overrides the scenario)",
                             cmd);
        if (const auto code = hymm::core::parseCommandLine(cmd, argc, argv)) return *code;

        const std::string dir = out.getValue() + "/";
        if (!mrpt::system::directoryExists(out.getValue()) &&
            !mrpt::system::createDirectory(out.getValue()))
            throw std::runtime_error("cannot create the folder '" + out.getValue() + "'");
        auto scenario = hymm::sim::Scenario::fromFile(sc.getValue());
        if (seed.isSet()) scenario.run.seed = seed.getValue();
        if (ids.getValue()) scenario.detector.known_ids = true;
        if (duration.isSet())
        {
            if (!(duration.getValue() > 0))
                throw std::invalid_argument("--duration " + std::to_string(duration.getValue()) +
                                            " must be > 0");
            scenario.run.duration_s = duration.getValue();
        }
        Truth truth;
        const std::vector<Frame> frames = simulate(scenario, truth);
        const std::string slam_ini = readFile(sl.getValue());

        // Returns beyond the dense map's range are free space only: not counted as seen.
        hymm::eval::LaserCoverageOptions lo;
        {
            mrpt::config::CConfigFileMemory cfg(slam_ini);
            lo.max_range_m = DenseSlam::fromConfig(cfg).hybridMap()->options().max_range_m;
        }
        const auto seen = hymm::eval::laserSeenOutline(truth.scans, truth.path, truth.outlines, lo);

        const ModeResult off = runMode(slam_ini, false, frames, truth, seen, nullptr);
        const ModeResult on = runMode(slam_ini, true, frames, truth, seen, &off);
        if (on.global.fused.size() != on.stats.delayed_fused)
            std::printf(
                "note: %zu extra points in the 'on' map, %zu fused by the pipeline (a points-layer "
                "voxel "
                "filter merges points)\n\n",
                on.global.fused.size(), on.stats.delayed_fused);
        if (!fig.getValue().empty())
        {
            const std::string p = fig.getValue() + "/" + prefix.getValue();
            saveFigure(off, truth, seen, p + "_store_off.png");
            saveFigure(on, truth, seen, p + "_store_on.png");
        }

        printTable(seen, off, on, truth);
        printAlignment(off, on, truth);
        hymm::eval::MetricsJson j;
        j.set("outline_samples", static_cast<unsigned long>(seen.samples.points.size()));
        j.set("seen_samples", static_cast<unsigned long>(seen.seen_samples));
        j.set("seen_fraction", seen.seenFraction());
        const auto sensor_only = hymm::dense::evaluateOutlines(seen.returns.points, truth.surfaces);
        j.set("true_pose_returns_mean_distance_m", sensor_only.mean_distance_m);
        j.set("true_pose_returns_p95_distance_m", sensor_only.p95_distance_m);
        writeMode(j.object("store_off"), off);
        writeMode(j.object("store_on"), on);
        writeStretches(j.object("landmark_error_along_path"), on, truth);
        j.save(dir + "result.json");

        const double got = on.local.coverage.seen_coverage,
                     without = off.local.coverage.seen_coverage;
        const bool pass = got >= kRequiredSeenCoverage && got > without;
        std::printf(
            "\n%s: in the landmark frame the store maps %.1f %% of the seen outline (required >= "
            "%.0f %%), "
            "off %.1f %%\n",
            pass ? "PASS" : "FAIL", 100 * got, 100 * kRequiredSeenCoverage, 100 * without);
        return pass ? 0 : 2;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-delayed-store-eval: error: " << mrpt::exception_to_str(e) << "\n";
        return 1;
    }
}
