// MRPT's own apps on hymm-slam's outputs (skipped when the app is not installed:
// `scripts/setup --peers` installs them): `icp-slam` on run.rawlog, `observations2map` with
// configs/mrpt/observations2map.ini on the map.simplemap of a short run (the first 200
// entries of rawlogs/ch3_objects.rawlog, configs/ch3_slam.ini) exits 0 and writes a
// .gridmap that MRPT's reader loads and that agrees with the run's own occupancy layer
// (map.hymm rendered at the final landmark estimates) cell by cell.
#include "grid_agreement.h"
#include "../support/mrpt_apps.h"

#include <gtest/gtest.h>
#include <hymm/app/SlamApp.h>
#include <hymm/dense/CHybridMetricMap.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>

#include <unistd.h>

namespace
{
namespace fs = std::filesystem;
const std::string kSrc = HYMM_SOURCE_DIR;

struct TempDir
{
    fs::path path = fs::temp_directory_path() / ("hymm_mrpt_apps_" + std::to_string(::getpid()));
    TempDir()
    {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
};

/** hymm-slam on the bundled chapter-3 sample into `dir`/run (0: the whole rawlog). */
hymm::app::SlamApp::Args ch3Run(const TempDir& dir, size_t stop_after)
{
    hymm::app::SlamApp::Args a;
    a.config = kSrc + "/configs/ch3_slam.ini";
    a.rawlog = kSrc + "/rawlogs/ch3_objects.rawlog";
    a.out_dir = (dir.path / "run").string();
    a.quiet = true;
    a.png = false;
    a.stop_after = stop_after;
    return a;
}

TEST(MrptApps, Observations2mapOnTheSimplemapBuildsAGridAgreeingWithOurs)
{
    if (!hymm::testing::mrptAppInstalled("observations2map")) GTEST_SKIP() << "MRPT's observations2map is not installed";
    TempDir dir;
    const auto a = ch3Run(dir, 200);
    std::ostringstream log;
    hymm::app::SlamApp(a).run(log);

    const std::string prefix = (dir.path / "mrpt_grid").string();
    const std::string cmd = "observations2map " + kSrc + "/configs/mrpt/observations2map.ini " + a.out_dir +
                            "/map.simplemap " + prefix + " > " + prefix + ".log 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    mrpt::maps::COccupancyGridMap2D g_mrpt;
    {
        mrpt::io::CFileGZInputStream f;
        ASSERT_TRUE(f.open(prefix + "_gridmap_no00.gridmap"));
        mrpt::serialization::archiveFrom(f) >> g_mrpt;
    }
    const auto ours = hymm::dense::CHybridMetricMap::loadFromFile(a.out_dir + "/map.hymm");
    const auto& g_ours = ours->renderedOccupancy();
    EXPECT_NEAR(g_mrpt.getResolution(), g_ours.getResolution(), 1e-6);  // the .ini's cell = the layer's

    hymm::testing::expectGridsAgree("observations2map", hymm::testing::compareGrids(g_ours, g_mrpt));
}

// MRPT's icp-slam maps run.rawlog (observation format: our pose, the input's odometry and
// the input's observations per frame) with MRPT's own demo config made headless: it ends
// where our estimate does. icp-slam does not read our poses; it needs the odometry.
TEST(MrptApps, IcpSlamMapsTheRunRawlog)
{
    if (!hymm::testing::icpSlamAvailable()) GTEST_SKIP() << "MRPT's icp-slam or its demo config is missing";
    TempDir dir;
    const auto a = ch3Run(dir, 0);
    std::ostringstream log;
    hymm::app::SlamApp slam(a);
    slam.run(log);

    const std::string logs = (dir.path / "icp").string();
    ASSERT_EQ(hymm::testing::runIcpSlam(a.out_dir + "/run.rawlog", logs), 0) << "icp-slam failed: " << logs << ".log";
    mrpt::maps::CSimpleMap sm;
    ASSERT_TRUE(sm.loadFromFile(logs + "/_finalmap_.simplemap"));
    ASSERT_GT(sm.size(), 10u);
    const auto last = std::get<0>(sm.get(sm.size() - 1))->getMeanVal();
    const auto& ours = slam.slam().path().back().pose;
    const double d = std::hypot(last.x() - ours.x(), last.y() - ours.y());
    std::cout << "[icp-slam] " << sm.size() << " keyframes, last at (" << last.x() << ", " << last.y()
              << "), ours (" << ours.x() << ", " << ours.y() << "): " << d << " m apart\n";
    EXPECT_LT(d, 1.5);  // 0.45 m after the 254 m loop (without the odometry: 9 m, lost)
}

}  // namespace
