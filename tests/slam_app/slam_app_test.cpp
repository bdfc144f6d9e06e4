// hymm-slam (SlamApp) on rawlogs/ch3_objects.rawlog with configs/ch3_slam.ini: every
// output is written, the path matches the ground truth, the dense maps lie on the true
// object outlines (read back from the files the app wrote, MRPT formats included), and
// bad inputs fail with an exception before anything is written.
#include <gtest/gtest.h>
#include <hymm/core/trajectory_io.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/denseslam/SlamApp.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <hymm/sim/ground_truth_io.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace
{
namespace fs = std::filesystem;
using hymm::denseslam::SlamApp;

const std::string kSrc = HYMM_SOURCE_DIR;
const std::string kRawlog = kSrc + "/rawlogs/ch3_objects.rawlog";
const std::string kConfig = kSrc + "/configs/ch3_slam.ini";
const std::string kGt = kSrc + "/rawlogs/ch3_objects_gt_";

// Measured with this config: path RMSE 0.55 m; outline mean
// distance away from the landmarks 0.36 m (occupancy) and 0.82 m (points); coverage
// 0.10 / 0.15 of the outlines. The bounds leave room for platform differences only.
constexpr double kMaxPathRmse = 0.8;            // [m]
constexpr double kMaxOccupancyMeanDist = 0.6;   // [m]
constexpr double kMaxPointsMeanDist = 1.2;      // [m]
constexpr double kMinCoverage = 0.05;
constexpr double kLandmarkRadius = 1.0;         // [m] returns on landmark trunks

struct TempDir
{
    fs::path path;
    TempDir()
    {
        path = fs::temp_directory_path() / ("hymm_slam_app_test_" + std::to_string(::getpid()));
        fs::remove_all(path);
    }
    ~TempDir() { fs::remove_all(path); }
};

std::vector<hymm::dense::Polygon> trueOutlines()
{
    std::vector<hymm::dense::Polygon> out;
    for (const auto& r : hymm::sim::readObjectOutlines(kGt + "objects.txt"))
        out.emplace_back(r.outline.begin(), r.outline.end());
    return out;
}

// Map points away from the true landmarks (their trunks are not object outlines).
std::vector<Eigen::Vector2d> awayFromLandmarks(const std::vector<Eigen::Vector2d>& pts)
{
    const auto lms = hymm::core::readLandmarksCsv(kGt + "landmarks.csv");
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

template <class T>
void readSerialized(const std::string& file, T& obj)
{
    mrpt::io::CFileGZInputStream f;
    ASSERT_TRUE(f.open(file)) << file;
    mrpt::serialization::archiveFrom(f) >> obj;
}

SlamApp::Args argsFor(const std::string& out)
{
    SlamApp::Args a;
    a.config = kConfig;
    a.rawlog = kRawlog;
    a.out_dir = out;
    a.gt_path = kGt + "path.tum";
    a.gt_landmarks = kGt + "landmarks.csv";
    a.gt_objects = kGt + "objects.txt";
    a.quiet = true;
    return a;
}

TEST(SlamApp, Ch3ObjectsWritesAccurateFeatureAndDenseMaps)
{
    TempDir tmp;
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
    std::ifstream mj(out + "/metrics.json");
    const std::string metrics((std::istreambuf_iterator<char>(mj)), std::istreambuf_iterator<char>());
    for (const char* key : {"\"dense\"", "\"points\"", "\"occupancy\"", "\"classic_grid\"",
                            "\"coverage\"", "\"p95_distance_m\""})
        EXPECT_NE(metrics.find(key), std::string::npos) << key;

    // Path from the written file against the truth.
    hymm::eval::TrajectoryEvaluator::Options to;
    to.association = hymm::eval::TrajectoryEvaluator::Association::Interpolate;
    const auto traj = hymm::eval::TrajectoryEvaluator(to).evaluate(
        hymm::core::readTum(out + "/path.tum"), hymm::core::readTum(kGt + "path.tum"));
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
    // Occupancy layer, read back as MRPT tools read it.
    mrpt::maps::COccupancyGridMap2D grid;
    readSerialized(out + "/occupancy.gridmap", grid);
    const auto occ = hymm::dense::evaluateOutlines(
        awayFromLandmarks(hymm::dense::occupiedCellCentres(grid, 0.8)), outlines);
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
    const auto cm = hymm::dense::evaluateOutlines(
        awayFromLandmarks(hymm::dense::occupiedCellCentres(classic, 0.8)), outlines);
    EXPECT_GT(cm.coverage, kMinCoverage);
}

TEST(SlamApp, MissingRawlogThrowsBeforeWriting)
{
    TempDir tmp;
    auto a = argsFor(tmp.path.string());
    a.rawlog = kSrc + "/rawlogs/no_such_file.rawlog";
    std::ostringstream log;
    EXPECT_ANY_THROW(SlamApp(a).run(log));
    EXPECT_FALSE(fs::exists(tmp.path));
}

TEST(SlamApp, MalformedIniThrowsBeforeWriting)
{
    TempDir tmp;
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
