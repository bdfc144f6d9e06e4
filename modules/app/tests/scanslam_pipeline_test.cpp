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

TEST(ScanSlamPipeline, Chapter5WorldAccurateAndConsistent)
{
    const auto cfg = hymm::core::openConfigFile(kRoot + "/configs/ch5_scanslam.ini");
    constexpr int kSeeds = 3;
    constexpr double kDuration = 45;  // [s] 135 m: the first straight and corner
    std::vector<double> nees_sum;
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
            nees_sum[i] += run.steps[i].nees;
        }
        // Landmarks were made and re-observed, and the filter stayed near the truth.
        size_t created = 0, updated = 0;
        for (const auto& [k, n] : run.counters)
        {
            if (k == "scan_landmarks.created") created = n;
            if (k == "scan_landmarks.updated") updated = n;
        }
        EXPECT_GE(created, 5u);
        EXPECT_GE(updated, 10 * created);
        EXPECT_LT(run.path_rmse_m, 0.5);
        EXPECT_LT(run.after_closure.rmse_xy_m, 0.5);
        EXPECT_LT(run.after_closure.rmse_phi, 1.5 * M_PI / 180);
        // Templates lie on the true outlines (the laser's range noise is 0.1 m).
        EXPECT_LT(run.template_outline_mean_m, 0.25);
    }
    // Run-averaged vehicle NEES (3 DOF) inside the 95 % band on most steps.
    for (auto& v : nees_sum) v /= kSeeds;
    const auto band = hymm::eval::averageNeesBounds(3, kSeeds, 0.95);
    EXPECT_GE(hymm::eval::fractionInsideBounds(nees_sum, band), 0.8);
}

}  // namespace
