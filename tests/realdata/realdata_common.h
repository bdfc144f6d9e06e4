// Helpers of the real-data tests (realdata_*_test.cpp): the datasets' folder, scratch
// folders, runs of hymm-slam's library class, and paths against GPS.
#pragma once

#include <gtest/gtest.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/datasets/import_dataset.h>
#include <hymm/app/MapPlot.h>
#include <hymm/app/SlamApp.h>
#include <hymm/app/slam_outputs.h>
#include <hymm/eval/LandmarkEvaluator.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <mrpt/math/wrap2pi.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace realdata
{
namespace fs = std::filesystem;
using hymm::io::StampedPose2D;
using hymm::denseslam::DenseSlam;
using hymm::app::SlamApp;
using hymm::eval::LandmarkEvaluator;
using hymm::eval::Se2Transform;
using hymm::eval::TrajectoryEvaluator;

#ifdef HYMM_REALDATA_SANITIZER_BUILD
inline constexpr bool kSanitizerBuild = true;
#elif defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitizerBuild = true;
#else
inline constexpr bool kSanitizerBuild = false;
#endif

inline std::string env(const char* name)
{
    const char* v = std::getenv(name);
    return v ? v : "";
}

inline std::string datasets() { return env("HYMM_DATASETS"); }

inline std::string sourceFile(const std::string& rel) { return std::string(HYMM_SOURCE_DIR) + "/" + rel; }

/** A fresh folder under the system temp dir, removed with its contents at the end. */
class ScratchDir
{
public:
    explicit ScratchDir(const std::string& name)
        : path_(fs::temp_directory_path() /
                ("hymm_realdata_" + name + "_" + std::to_string(::getpid())))
    {
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~ScratchDir()
    {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
    fs::path path_;
};

/** Runs the SLAM app (no figure, no progress) and times the whole run. */
struct SlamRun
{
    std::unique_ptr<SlamApp> app;
    double seconds = 0;
    const DenseSlam& slam() const { return app->slam(); }
};

/** `config`: a path in the source tree, or an absolute one (a config written by the test). */
inline SlamRun runSlam(const std::string& config, const std::string& rawlog, const std::string& out)
{
    SlamApp::Args a;
    a.config = fs::path(config).is_absolute() ? config : sourceFile(config);
    a.rawlog = rawlog;
    a.out_dir = out;
    a.quiet = true;
    a.png = false;
    SlamRun r;
    r.app = std::make_unique<SlamApp>(a);
    std::ostringstream log;
    const auto t0 = std::chrono::steady_clock::now();
    r.app->run(log);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

inline std::vector<StampedPose2D> estimatedPath(const DenseSlam& slam)
{
    std::vector<StampedPose2D> out;
    for (const auto& s : slam.path()) out.push_back({s.t, s.pose[0], s.pose[1], s.pose[2]});
    return out;
}

inline std::vector<hymm::eval::LandmarkEstimate> estimatedLandmarks(const DenseSlam& slam)
{
    std::vector<hymm::eval::LandmarkEstimate> out;
    for (long id : slam.ekf().landmarkIds())
    {
        if (slam.ekf().landmarkBlock(id).dim != 2) continue;
        hymm::eval::LandmarkEstimate e;
        e.id = id;
        e.position = slam.ekf().landmarkMean(id);
        e.cov = slam.ekf().landmarkCov(id);
        e.has_cov = true;
        out.push_back(e);
    }
    return out;
}

/** Path against GPS fixes (positions only): interpolated at the estimate's times across
 *  gaps of at most 0.5 s, with the SE(2) transform fitted on the first `fit_distance`
 *  metres of the run (0: on the whole run). */
inline TrajectoryEvaluator::Result againstGps(const std::vector<StampedPose2D>& path,
                                       const std::vector<StampedPose2D>& gps, double fit_distance)
{
    TrajectoryEvaluator::Options o;
    o.association = TrajectoryEvaluator::Association::Interpolate;
    o.time_tolerance = 0.5;
    o.align = true;
    o.align_fit_distance = fit_distance;
    return TrajectoryEvaluator(o).evaluate(path, gps);
}

inline void printSummary(const std::string& name, const SlamRun& run)
{
    const auto& s = run.slam().stats();
    const auto& p = run.slam().path();
    const double span = p.empty() ? 0.0 : p.back().t - p.front().t;
    std::cout << std::fixed << std::setprecision(3) << "[" << name << "] frames " << s.frames
              << ", observations " << s.observations << " (associated " << s.associated
              << ", created " << s.created << ", gate rejects " << s.rejected_gate
              << ", ambiguous " << s.ambiguous << "), landmarks " << run.slam().ekf().numLandmarks()
              << "\n[" << name << "] run " << run.seconds << " s for " << span
              << " s of data: " << span / run.seconds << "x real time\n";
}

/** Figure in the ground-truth frame: the estimate moved by `T`, over the truth. */
inline void writeFigure(const std::string& file, const DenseSlam& slam, const Se2Transform& T,
                 const std::vector<StampedPose2D>& true_path,
                 const std::vector<hymm::io::LandmarkRecord>& true_landmarks)
{
    hymm::app::MapPlot plot;
    for (const auto& s : slam.path()) plot.estimated_path.push_back(T.apply(s.pose.head<2>()));
    const Eigen::Matrix2d R = T.rotation();
    for (const auto& e : estimatedLandmarks(slam))
        plot.estimated_landmarks.push_back({T.apply(e.position), R * e.cov * R.transpose()});
    for (const auto& g : true_path) plot.true_path.emplace_back(g.x, g.y);
    for (const auto& l : true_landmarks) plot.true_landmarks.emplace_back(l.x, l.y);
    for (const auto& p : hymm::app::makeMapPlot(slam, nullptr).dense_points)
        plot.dense_points.push_back(T.apply(p));
    plot.max_side = 1000;
    hymm::app::writeMapPng(plot, file);
    std::cout << "wrote " << file << "\n";
}

inline void maybeWriteFigure(const std::string& name, const DenseSlam& slam, const Se2Transform& T,
                      const std::vector<StampedPose2D>& true_path,
                      const std::vector<hymm::io::LandmarkRecord>& true_landmarks)
{
    const std::string dir = env("HYMM_REALDATA_FIGURES");
    if (dir.empty()) return;
    fs::create_directories(dir);
    writeFigure(dir + "/" + name + ".png", slam, T, true_path, true_landmarks);
}

/** Pose `g` expressed in the frame whose origin is the pose `o`. */
inline StampedPose2D relativeTo(const StampedPose2D& o, const StampedPose2D& g)
{
    const double c = std::cos(o.phi), s = std::sin(o.phi);
    const double dx = g.x - o.x, dy = g.y - o.y;
    return {g.t, c * dx + s * dy, -s * dx + c * dy, mrpt::math::wrapToPi(g.phi - o.phi)};
}

/** The car park converted into `dir`/data (rawlog, GPS, beacon survey). */
inline void importCarPark(const ScratchDir& dir)
{
    hymm::datasets::importDataset("carpark", {datasets() + "/acfr_carpark"}, dir.file("data"),
                                  sourceFile("configs/datasets/carpark.ini"));
}

/** A config file's text. */
inline std::string readConfig(const std::string& path)
{
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace realdata
