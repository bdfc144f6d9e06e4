// hymm-slam (SlamApp) on rawlogs/ch3_objects.rawlog with configs/ch3_slam.ini: every
// output is written, the path matches the ground truth, the dense maps lie on the true
// object outlines (read back from the files the app wrote, MRPT formats included), and
// bad inputs fail with an exception before anything is written. Every chapter-4 layer
// on: all_layers_test.cpp.
#include "ch3_sample.h"
#include "slam_app_files.h"

#include <gtest/gtest.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/app/SlamApp.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <hymm/eval/se2_alignment.h>
#include <hymm/sim/ground_truth_io.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace
{
namespace fs = std::filesystem;
using hymm::app::SlamApp;
using namespace hymm::test;

const std::string kSrc = HYMM_SOURCE_DIR;
const std::string kConfig = kSrc + "/configs/ch3_slam.ini";
const std::string& kGt = hymm::test::kCh3Gt;

// Measured with this config: path RMSE 0.55 m; outline mean
// distance away from the landmarks 0.36 m (occupancy) and 0.82 m (points); coverage
// 0.10 / 0.15 of the outlines. The bounds leave room for platform differences only.
constexpr double kMaxPathRmse = 0.8;            // [m]
constexpr double kMaxOccupancyMeanDist = 0.6;   // [m]
constexpr double kMaxPointsMeanDist = 1.2;      // [m]
constexpr double kMinCoverage = 0.05;
constexpr double kLandmarkRadius = 1.0;         // [m] returns on landmark trunks

// Cells of a .gridmap as MRPT reads it (cell = P(free)) with P(free) < 0.2, i.e. the
// cells HYMM rendered with P(occupied) > 0.8.
std::vector<Eigen::Vector2d> mrptOccupiedCells(const mrpt::maps::COccupancyGridMap2D& grid)
{
    std::vector<Eigen::Vector2d> out;
    for (unsigned y = 0; y < grid.getSizeY(); ++y)
        for (unsigned x = 0; x < grid.getSizeX(); ++x)
            if (grid.getCell(x, y) < 0.2f) out.emplace_back(grid.idx2x(x), grid.idx2y(y));
    return out;
}

// Map points away from the true landmarks (their trunks are not object outlines).
std::vector<Eigen::Vector2d> awayFromLandmarks(const std::vector<Eigen::Vector2d>& pts)
{
    const auto lms = hymm::io::readLandmarksCsv(kGt + "landmarks.csv");
    std::vector<Eigen::Vector2d> out;
    for (const auto& p : pts)
    {
        bool near = false;
        for (const auto& l : lms)
            near = near || (p - Eigen::Vector2d(l.x, l.y)).norm() < kLandmarkRadius;
        if (!near) out.push_back(p);
    }
    return out;
}

SlamApp::Args argsFor(const std::string& out) { return hymm::test::ch3SampleArgs(kConfig, out); }

TEST(SlamApp, Ch3ObjectsWritesAccurateFeatureAndDenseMaps)
{
    TempDir tmp("hymm_slam_app_test_");
    const std::string out = tmp.path.string();
    SlamApp app(argsFor(out));
    std::ostringstream log;
    app.run(log);

    for (const char* f : {"path.tum", "landmarks.csv", "map.png", "metrics.json", "summary.txt",
                          "timing.csv", "regions.txt", "points.png", "points.bin", "points.txt",
                          "occupancy.png", "occupancy.gridmap", "classic_grid.png",
                          "classic_grid.gridmap"})
    {
        const fs::path p = fs::path(out) / f;
        EXPECT_TRUE(fs::exists(p)) << f;
        if (fs::exists(p))
        {
            EXPECT_GT(fs::file_size(p), 0u) << f;
        }
    }
    const std::string metrics = readFile(out + "/metrics.json");
    for (const char* key : {"\"dense\"", "\"points\"", "\"occupancy\"", "\"classic_grid\"",
                            "\"coverage\"", "\"p95_distance_m\""})
        EXPECT_NE(metrics.find(key), std::string::npos) << key;

    // Path from the written file against the truth.
    hymm::eval::TrajectoryEvaluator::Options to;
    to.association = hymm::eval::TrajectoryEvaluator::Association::Interpolate;
    const auto traj = hymm::eval::TrajectoryEvaluator(to).evaluate(
        hymm::io::readTum(out + "/path.tum"), hymm::io::readTum(kGt + "path.tum"));
    EXPECT_EQ(traj.errors.size(), app.slam().path().size());
    EXPECT_LT(traj.position_rmse, kMaxPathRmse);

    // Regions were built and the layers hold returns.
    ASSERT_NE(app.slam().partition(), nullptr);
    EXPECT_GT(app.slam().partition()->size(), 10u);
    hymm::ltr::RegionPartition::Options po;
    hymm::ltr::RegionPartition reread(po);
    reread.loadFromFile(out + "/regions.txt");
    EXPECT_EQ(reread.size(), app.slam().partition()->size());

    const auto outlines = trueOutlines();
    // Occupancy layer, read back as MRPT tools read it: a cell holds P(free), so the
    // outlines must lie on cells MRPT itself calls occupied.
    mrpt::maps::COccupancyGridMap2D grid;
    readSerialized(out + "/occupancy.gridmap", grid);
    const auto occ = hymm::dense::evaluateOutlines(
        awayFromLandmarks(mrptOccupiedCells(grid)), outlines);
    EXPECT_GT(occ.points, 50u);
    EXPECT_LT(occ.mean_distance_m, kMaxOccupancyMeanDist);
    EXPECT_GT(occ.coverage, kMinCoverage);

    mrpt::maps::CSimplePointsMap pts;
    readSerialized(out + "/points.bin", pts);
    EXPECT_GT(pts.size(), 1000u);
    const auto pm = hymm::dense::evaluateOutlines(awayFromLandmarks(hymm::dense::pointsOf(pts)), outlines);
    EXPECT_LT(pm.mean_distance_m, kMaxPointsMeanDist);
    EXPECT_GT(pm.coverage, kMinCoverage);

    // The classic grid is written in the same format and covers the outlines it saw.
    mrpt::maps::COccupancyGridMap2D classic;
    readSerialized(out + "/classic_grid.gridmap", classic);
    const auto cm = hymm::dense::evaluateOutlines(awayFromLandmarks(mrptOccupiedCells(classic)), outlines);
    EXPECT_GT(cm.coverage, kMinCoverage);

    // The common rotation of the landmark map and the filter's own 1-sigma of it: rebuilt
    // here from the filter with a numeric Jacobian of the fit and the joint covariance of
    // the paired landmarks (metrics.json pairs each estimate with the true landmark
    // within 3 m).
    const auto& ekf = app.slam().ekf();
    const auto truth = hymm::io::readLandmarksCsv(kGt + "landmarks.csv");
    std::vector<Eigen::Vector2d> est, tru;
    std::vector<size_t> offsets;
    for (long id : ekf.landmarkIds())
    {
        if (ekf.landmarkBlock(id).dim != 2) continue;
        const Eigen::Vector2d e = ekf.landmarkMean(id);
        const hymm::io::LandmarkRecord* best = nullptr;
        double best_d = 3.0;
        for (const auto& l : truth)
            if (const double d = (Eigen::Vector2d(l.x, l.y) - e).norm(); d <= best_d) best_d = d, best = &l;
        if (!best) continue;
        est.push_back(e);
        tru.emplace_back(best->x, best->y);
        offsets.push_back(ekf.landmarkBlock(id).offset);
    }
    ASSERT_GE(est.size(), 10u);
    const double phi = hymm::eval::alignSE2(est, tru)->phi;
    Eigen::RowVectorXd J(2 * est.size());
    for (Eigen::Index k = 0; k < J.size(); ++k)
    {
        auto plus = est, minus = est;
        plus[k / 2][k % 2] += 1e-6;
        minus[k / 2][k % 2] -= 1e-6;
        J(k) = (hymm::eval::alignSE2(plus, tru)->phi - hymm::eval::alignSE2(minus, tru)->phi) / 2e-6;
    }
    Eigen::MatrixXd P(J.size(), J.size());
    for (size_t a = 0; a < offsets.size(); ++a)
        for (size_t b = 0; b < offsets.size(); ++b)
            P.block<2, 2>(2 * a, 2 * b) = ekf.cov().block<2, 2>(offsets[a], offsets[b]);
    const double std_deg = std::sqrt((J * P * J.transpose())(0, 0)) * 180.0 / M_PI;
    EXPECT_NEAR(denseMetric(metrics, "landmark_alignment", "phi_deg"), phi * 180.0 / M_PI, 1e-6);
    EXPECT_NEAR(denseMetric(metrics, "landmark_alignment", "phi_std_deg"), std_deg, 1e-6 * std_deg);
    // Measured: -0.13 deg against 0.44 deg (20 seeds of this scenario: mean square of the
    // normalised rotation 1.49, docs/results.md). Beyond 3 sigma would mean an inconsistent map.
    EXPECT_GT(std_deg, 0.1);
    EXPECT_LT(std::abs(denseMetric(metrics, "landmark_alignment", "phi_normalised")), 3.0);
}

TEST(SlamApp, MissingRawlogThrowsBeforeWriting)
{
    TempDir tmp("hymm_slam_app_test_");
    auto a = argsFor(tmp.path.string());
    a.rawlog = kSrc + "/rawlogs/no_such_file.rawlog";
    std::ostringstream log;
    EXPECT_ANY_THROW(SlamApp(a).run(log));
    EXPECT_FALSE(fs::exists(tmp.path));
}

TEST(SlamApp, MalformedIniThrowsBeforeWriting)
{
    TempDir tmp("hymm_slam_app_test_");
    const fs::path ini = fs::temp_directory_path() /
                         ("hymm_slam_app_test_bad_" + std::to_string(::getpid()) + ".ini");
    for (const std::string bad : {"dense_layers = points,walls\n", "no_such_key = 1\n"})
    {
        {
            std::ofstream f(ini);
            f << "[DenseSlam]\nlandmark_source = bearing_range\n" << bad;
        }
        auto a = argsFor(tmp.path.string());
        a.config = ini.string();
        std::ostringstream log;
        EXPECT_ANY_THROW(SlamApp(a).run(log)) << bad;
        EXPECT_FALSE(fs::exists(tmp.path)) << bad;
    }
    {
        std::ofstream f(ini);
        f << "[LtrPartition]\nmin_vertex_correlation = high\n";
    }
    auto a = argsFor(tmp.path.string());
    a.config = ini.string();
    std::ostringstream log;
    EXPECT_ANY_THROW(SlamApp(a).run(log));
    fs::remove(ini);
}

}  // namespace

// ---- reliability: output folder, run warnings, --strict --------------------------------

namespace reliability
{
const std::string kCh2 = kSrc + "/rawlogs/ch2_landmarks.rawlog";

fs::path scratch(const std::string& name)
{
    const fs::path p = fs::temp_directory_path() /
                       ("hymm_slam_app_rel_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(p);
    return p;
}

// The bearing-range-only chapter-2 rawlog under a laser-landmark config with no dense
// part: every entry reads cleanly, but no observation can be used.
SlamApp::Args unusableRun(const fs::path& out)
{
    const fs::path ini = out.string() + ".ini";
    std::ofstream(ini) << "[DenseSlam]\nlandmark_source = laser_trees\n";
    SlamApp::Args a;
    a.config = ini.string();
    a.rawlog = kCh2;
    a.out_dir = out.string();
    a.quiet = true;
    a.png = false;
    return a;
}
}  // namespace reliability

TEST(SlamAppReliability, RunThatUsesNoObservationWarnsOnStderrAndInTheSummary)
{
    const auto out = reliability::scratch("warn");
    std::ostringstream log;
    SlamApp(reliability::unusableRun(out)).run(log);
    EXPECT_NE(log.str().find("hymm-slam: warning: none of the rawlog's"), std::string::npos)
        << log.str();
    EXPECT_NE(log.str().find("no landmark observation reached the filter"), std::string::npos);
    const auto summary = readFile(out / "summary.txt");
    EXPECT_NE(summary.find("warning              none of the rawlog's"), std::string::npos)
        << summary;
    EXPECT_NE(summary.find("of a kind this config does not use"), std::string::npos);
    fs::remove_all(out);
    fs::remove(out.string() + ".ini");
}

// The chapter-2 sample with two comments (a class hymm-slam does not read) in every
// frame and two frames stamped before the one they follow: most observations unused,
// counted by class name, and time going backwards, each a warning; --strict fails.
TEST(SlamAppReliability, MostObservationsUnusedAndTimeBackwardsAreWarningsNamingTheCause)
{
    const auto out = reliability::scratch("mostly");
    const fs::path rawlog = out.string() + ".rawlog";
    mrpt::obs::CRawlog log_in, log_out;
    ASSERT_TRUE(log_in.loadFromRawLogFile(reliability::kCh2));
    size_t frames = 0;
    std::vector<mrpt::Clock::time_point> stamps;
    for (size_t i = 0; i < log_in.size(); ++i)
    {
        if (log_in.getType(i) != mrpt::obs::CRawlog::etSensoryFrame)
        {
            log_out.insert(log_in.getAsAction(i));
            continue;
        }
        auto sf = log_in.getAsObservations(i);
        ASSERT_FALSE(sf->empty());
        auto first = *sf->begin();
        stamps.push_back(first->timestamp);
        if (frames == 10 || frames == 20) first->timestamp = stamps[frames - 5];  // backwards
        for (int k = 0; k < 2; ++k)
        {
            auto c = mrpt::obs::CObservationComment::Create();
            c->text = "not a measurement";
            c->timestamp = first->timestamp;
            sf->insert(c);
        }
        log_out.insert(*sf);
        ++frames;
    }
    ASSERT_GT(frames, 30u);
    ASSERT_TRUE(log_out.saveToRawLogFile(rawlog.string()));

    SlamApp::Args a;
    a.config = kSrc + "/configs/ch2_slam.ini";
    a.rawlog = rawlog.string();
    a.out_dir = out.string();
    a.quiet = true;
    a.png = false;
    std::ostringstream log;
    SlamApp(a).run(log);
    const std::string comments = "mrpt::obs::CObservationComment " + std::to_string(2 * frames);
    const auto summary = readFile(out / "summary.txt");
    for (const std::string& text : {log.str(), summary})
    {
        EXPECT_NE(text.find("most observations were not used: " + std::to_string(2 * frames) + " of " +
                            std::to_string(3 * frames)),
                  std::string::npos)
            << text;
        EXPECT_NE(text.find("unsupported types: " + comments + ")"), std::string::npos) << text;
        EXPECT_NE(text.find("time went backwards 2 times"), std::string::npos) << text;
    }
    EXPECT_NE(log.str().find("hymm-slam: warning: most observations"), std::string::npos);
    EXPECT_NE(summary.find("unsupported obs.     " + comments + "\n"), std::string::npos) << summary;

    a.strict = true;
    EXPECT_THROW(SlamApp(a).run(log), std::runtime_error);
    EXPECT_TRUE(fs::is_empty(out)) << "--strict: no results";
    fs::remove_all(out);
    fs::remove(rawlog);
}

TEST(SlamAppReliability, StrictMakesARunWarningAFailureWithNoResults)
{
    const auto out = reliability::scratch("strict");
    auto a = reliability::unusableRun(out);
    a.strict = true;
    std::ostringstream log;
    try
    {
        SlamApp(a).run(log);
        FAIL() << "--strict run with warnings succeeded";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("--strict"), std::string::npos) << e.what();
    }
    ASSERT_TRUE(fs::is_directory(out)) << "the folder is made before the work";
    EXPECT_TRUE(fs::is_empty(out)) << "no results, no staging folder left";
    fs::remove_all(out);
    fs::remove(out.string() + ".ini");
}

TEST(SlamAppReliability, AnEarlierRunsResultsAreReplacedNotMixed)
{
    const auto out = reliability::scratch("stale");
    auto a = reliability::unusableRun(out);
    a.png = true;
    std::ostringstream log;
    SlamApp(a).run(log);
    ASSERT_TRUE(fs::exists(out / "map.png"));
    std::ofstream(out / "my_notes.txt") << "kept";
    a.png = false;  // the second run writes no map.png
    SlamApp(a).run(log);
    EXPECT_FALSE(fs::exists(out / "map.png")) << "stale result of the first run";
    EXPECT_TRUE(fs::exists(out / "summary.txt"));
    EXPECT_EQ(readFile(out / "my_notes.txt"), "kept");
    const auto manifest = readFile(out / ".hymm-outputs");
    EXPECT_NE(manifest.find("summary.txt\n"), std::string::npos);
    EXPECT_EQ(manifest.find("map.png"), std::string::npos);
    for (const auto& e : fs::directory_iterator(out))
        EXPECT_EQ(e.path().filename().string().find(".hymm-partial"), std::string::npos);
    fs::remove_all(out);
    fs::remove(out.string() + ".ini");
}

TEST(SlamAppReliability, BadOutputFolderFailsBeforeTheRawlogIsProcessed)
{
    const auto base = reliability::scratch("badout");
    fs::create_directories(base);
    std::ofstream(base / "a_file") << "x";
    // A rawlog cut short: if the folder were checked after the rawlog, the error would
    // be about the rawlog.
    const fs::path cut = base / "cut.rawlog";
    {
        const auto bytes = readFile(reliability::kCh2);
        std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    }
    for (const fs::path& bad : {base / "a_file", base / "missing_parent" / "out"})
    {
        auto a = reliability::unusableRun(bad);
        a.config = (base / "cfg.ini").string();
        std::ofstream(a.config) << "[DenseSlam]\nlandmark_source = laser_trees\n";
        a.rawlog = cut.string();
        std::ostringstream log;
        try
        {
            SlamApp(a).run(log);
            FAIL() << bad;
        }
        catch (const std::runtime_error& e)
        {
            EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
        }
    }
    fs::remove_all(base);
}
