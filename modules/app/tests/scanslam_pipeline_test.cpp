// Scan-SLAM through the pipeline (DenseSlam with landmark_source = scan_landmarks, the
// chapter-5 configs) on short simulated runs of the chapter-5 world, scored against the
// simulator's truth: path and landmark pose errors, and the vehicle NEES over several
// seeds inside the chi-square band.
#include <gtest/gtest.h>
#include <hymm/app/ScanSlamStudy.h>
#include <hymm/core/config_utils.h>
#include <hymm/eval/nees.h>

#include <cmath>
#include <string>
#include <vector>

namespace
{
const std::string kRoot = HYMM_SOURCE_DIR;

hymm::sim::Scenario shortRun(long seed, double duration_s)
{
    auto s = hymm::sim::Scenario::fromFile(kRoot + "/configs/sim/ch5_scanslam.ini");
    s.run.seed = seed;
    s.run.duration_s = duration_s;
    return s;
}

// What the pipeline achieves today on the Table 5.1 noise (docs/results.md, "Scan-SLAM"):
// landmarks made, observed and kept finite, and the path much closer to the truth than
// the odometry alone. The vehicle NEES is recorded, not asserted: the filter is
// overconfident on this world (run-averaged NEES inside the 95 % band on about half the
// steps), a known open problem listed in the results.
TEST(ScanSlamPipeline, Chapter5WorldBeatsOdometryAndStaysFinite)
{
    const auto cfg = hymm::core::openConfigFile(kRoot + "/configs/ch5_scanslam.ini");
    constexpr int kSeeds = 3;
    constexpr double kDuration = 45;  // [s] 135 m: the first straight and corner
    std::vector<double> nees_sum;
    double slam_sum = 0, dr_sum = 0;
    for (int seed = 1; seed <= kSeeds; ++seed)
    {
        const auto run = hymm::app::runScanSlamStudy(shortRun(seed, kDuration), *cfg);
        SCOPED_TRACE("seed " + std::to_string(seed));
        ASSERT_FALSE(run.steps.empty());
        if (nees_sum.empty()) nees_sum.assign(run.steps.size(), 0.0);
        ASSERT_EQ(run.steps.size(), nees_sum.size());
        for (size_t i = 0; i < run.steps.size(); ++i)
        {
            ASSERT_TRUE(run.steps[i].estimate.allFinite());
            ASSERT_TRUE(run.steps[i].cov.allFinite());
            nees_sum[i] += run.steps[i].nees;
        }
        size_t created = 0, updated = 0;
        for (const auto& [k, n] : run.counters)
        {
            if (k == "scan_landmarks.created") created = n;
            if (k == "scan_landmarks.updated") updated = n;
        }
        EXPECT_GE(created, 8u);
        EXPECT_GE(updated, 3 * created);
        EXPECT_EQ(run.after_closure.landmarks, created);
        // Every run closer to the truth than its dead reckoning.
        EXPECT_LT(run.path_rmse_m, 0.9 * run.dead_reckoning_rmse_m);
        slam_sum += run.path_rmse_m;
        dr_sum += run.dead_reckoning_rmse_m;
    }
    // Over the seeds, well below the odometry's error (measured: 58 % of it).
    EXPECT_LT(slam_sum, 0.7 * dr_sum);
    for (auto& v : nees_sum) v /= kSeeds;
    const auto band = hymm::eval::averageNeesBounds(3, kSeeds, 0.95);
    RecordProperty("vehicle_nees_fraction_inside_95",
                   std::to_string(hymm::eval::fractionInsideBounds(nees_sum, band)));
}

}  // namespace
