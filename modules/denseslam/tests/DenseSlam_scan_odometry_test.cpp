// DenseSlam with [ScanOdometry] on the chapter-5 world (objects only: the pipeline has
// no landmark to observe, so the path is the odometry's), simulated in process and
// checked against the simulator's truth: the scan-aligned path stays far closer than
// the wheels' and its covariance covers its error; the run state refuses the option.
#include "sim_feed.h"

#include <gtest/gtest.h>
#include <hymm/core/StrictConfigFile.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/sim/Scenario.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <vector>
#include <functional>
#include <optional>
#include <string>

namespace
{
using hymm::denseslam::DenseSlam;

const std::string kRoot = HYMM_SOURCE_DIR;

DenseSlam pipeline(bool scan_odometry)
{
    std::string text = "[DenseSlam]\nlandmark_source = bearing_range\n[Laser]\nstd_range_m = 0.1\nstd_bearing_deg = 1\n";
    if (scan_odometry) text += "[ScanOdometry]\nenabled = true\n";
    const auto cfg = hymm::core::StrictConfigFile::fromText(text, "scan odometry test");
    std::optional<DenseSlam> slam;
    cfg.load([&](const mrpt::config::CConfigFileBase& c) { slam.emplace(DenseSlam::fromConfig(c)); });
    cfg.checkAllSectionsKnown();
    return std::move(*slam);
}

struct PathError
{
    double rmse = 0;       //!< [m] position, over the frames
    double mean_nees = 0;  //!< 3 DOF, over the frames
};

PathError runWorld(uint32_t seed, bool scan_odometry, const std::function<void(DenseSlam&)>& inspect = {})
{
    hymm::sim::Scenario sc = hymm::sim::Scenario::fromFile(kRoot + "/configs/sim/ch5_scanslam.ini");
    sc.run.duration_s = 40;
    sc.run.seed = seed;
    DenseSlam slam = pipeline(scan_odometry);
    hymm::sim::Simulator sim(sc);
    double sq = 0, nees = 0;
    size_t n = 0;
    hymm::denseslam::testing::runFrames(sim, slam, [&](const hymm::sim::SimFrame& f) {
        Eigen::Vector3d e = slam.ekf().vehiclePose() - f.true_pose;
        e.z() = std::remainder(e.z(), 2 * M_PI);
        sq += e.head<2>().squaredNorm();
        nees += e.dot(slam.ekf().vehicleCov().ldlt().solve(e));
        ++n;
    });
    EXPECT_TRUE(slam.ekf().mean().allFinite());
    if (inspect) inspect(slam);
    return {std::sqrt(sq / static_cast<double>(n)), nees / static_cast<double>(n)};
}
}  // namespace

TEST(DenseSlamScanOdometry, ConsecutiveScansKeepThePathCloserThanTheWheelsAndConsistent)
{
    // 40 s (200 scans) of the chapter-5 vehicle (3 m/s, 0.5 m/s and 5 deg of speed and
    // steering noise, no landmark) on six seeds, the default matcher (correlative).
    // Measured: path RMSE 1.17 / 1.61 / 0.95 / 1.98 / 0.70 / 0.69 m against the wheels'
    // 4.86 / 3.76 / 3.34 / 0.61 / 3.69 / 3.11 m (seed 4: the wheels' errors cancelled);
    // mean NEES 2.0 / 5.2 / 2.5 / 2.8 / 1.3 / 1.6 (wheels 3.1 / 5.2 / 4.1 / 1.4 / 2.6 / 3.0).
    std::vector<double> wheel_rmse, scan_rmse;
    for (uint32_t seed = 1; seed <= 6; ++seed)
    {
        const PathError wheels = runWorld(seed, false);
        const PathError scans = runWorld(seed, true, [&](DenseSlam& slam) {
            const auto* odo = slam.scanOdometry();
            ASSERT_NE(odo, nullptr);
            const auto& st = odo->stats();
            size_t failed = 0;
            for (const auto& [reason, count] : st.align_failed) failed += count;
            EXPECT_EQ(st.scans, st.no_reference + st.too_few_points + st.gated + st.fused + failed);
            EXPECT_GE(st.fused, st.scans * 9 / 10);
            EXPECT_EQ(slam.stats().predictions, slam.stats().frames);
            // Its reference scan and pending increment are not in the run state: refused.
            EXPECT_NE(slam.stateUnsupported().find("ScanOdometry"), std::string::npos);
            mrpt::io::CMemoryStream mem;
            auto ar = mrpt::serialization::archiveFrom(mem);
            EXPECT_THROW(slam.saveState(ar), std::runtime_error);
        });
        std::printf("seed %u: path RMSE wheels %.3f m, scans %.3f m; mean NEES %.2f, %.2f\n", seed, wheels.rmse,
                    scans.rmse, wheels.mean_nees, scans.mean_nees);
        wheel_rmse.push_back(wheels.rmse);
        scan_rmse.push_back(scans.rmse);
        // One run's mean NEES over its (correlated) steps: a consistent filter stays
        // near 3; over-confidence of the fused increments shows as a mean far above it.
        EXPECT_LT(scans.mean_nees, 6.0) << "seed " << seed;
    }
    std::sort(wheel_rmse.begin(), wheel_rmse.end());
    std::sort(scan_rmse.begin(), scan_rmse.end());
    // Medians (the 3rd and 4th of six, averaged).
    EXPECT_LT(scan_rmse[2] + scan_rmse[3], 0.5 * (wheel_rmse[2] + wheel_rmse[3]));
}
