// Noise calibration on long synthetic runs (20 min at 50 Hz) the test generates: per-sample
// noise recovered at every window length, delays and scale errors found. 1-2 s each in
// Release, 30-100 s under the sanitizers (label 'long': the Release stage runs them; the
// calibration's input checks and skip paths run under the sanitizers in
// NoiseCalibration_test.cpp).
#include <gtest/gtest.h>
#include <hymm/datasets/NoiseCalibration.h>

#include "noise_calibration_runs.h"

namespace
{
using hymm::datasets::NoiseCalibrationOptions;
using hymm::test::makeRun;

TEST(NoiseCalibrationTest, PerSampleControlNoiseIsRecoveredAtEveryWindowLength)
{
    const double std_v = 0.1, std_w = 10.0;
    const auto run = makeRun(1200, std_v, std_w, 7);
    NoiseCalibrationOptions o;
    o.windows_s = {0.5, 1, 2, 5};
    o.fit_min_window_s = 0.5;
    const auto cal = hymm::datasets::calibrateOdometryNoise(run.commands, run.truth, o);

    EXPECT_NEAR(cal.joint.std_speed_mps, std_v, 0.05 * std_v);
    EXPECT_NEAR(cal.joint.std_turn_rate_deg_s, std_w, 0.05 * std_w);
    // Close to 3 (3 DOF); a little below, because the truth noise estimated from second
    // differences also holds the simulated 50 Hz control jitter.
    EXPECT_GT(cal.joint.mean_nees, 2.5);
    EXPECT_LT(cal.joint.mean_nees, 3.2);
    ASSERT_EQ(cal.per_window.size(), 4u);
    for (const auto& f : cal.per_window)
    {
        // White per-sample noise: every length gives the same values (within 3 se).
        EXPECT_NEAR(f.std_speed_mps, std_v, 3 * f.se_speed_mps + 0.02 * std_v) << f.window_s;
        EXPECT_NEAR(f.std_turn_rate_deg_s, std_w, 3 * f.se_turn_rate_deg_s + 0.02 * std_w)
            << f.window_s;
        // ... and the joint values predict the heading variance of every length.
        EXPECT_NEAR(f.heading_ms_deg2 / f.heading_model_deg2, 1.0, 0.2) << f.window_s;
    }
    // Variance grows linearly with the window (random walk).
    EXPECT_NEAR(cal.heading_growth_exponent, 1.0, 0.15);
    EXPECT_NEAR(cal.bias.lag_s, 0.0, 1e-9);
    EXPECT_NEAR(cal.bias.turn_scale, 1.0, 0.02);
    EXPECT_NEAR(cal.bias.speed_scale, 1.0, 0.05);
    EXPECT_TRUE(cal.skipped.empty());
    EXPECT_EQ(cal.truth_breaks, 0u);
}

TEST(NoiseCalibrationTest, LongWindowFitIsTheDefaultAndMatchesWhiteNoise)
{
    const auto run = makeRun(1200, 0.05, 5.0, 11);
    NoiseCalibrationOptions o;
    o.max_lag_s = 0.1;
    const auto cal = hymm::datasets::calibrateOdometryNoise(run.commands, run.truth, o);
    EXPECT_DOUBLE_EQ(cal.fit_min_window_s, 5.0);
    EXPECT_EQ(cal.per_window.size(), 7u);  // 0.2 .. 20 s
    EXPECT_NEAR(cal.joint.std_speed_mps, 0.05, 0.1 * 0.05);
    EXPECT_NEAR(cal.joint.std_turn_rate_deg_s, 5.0, 0.1 * 5.0);
}

TEST(NoiseCalibrationTest, DelayAndScaleErrorsAreFoundAndShowAsFasterGrowth)
{
    // The robot runs 10 samples (0.2 s) behind its commands, 10 % slower, turning 5 % less.
    const auto run = makeRun(1200, 0.01, 1.0, 3, 0.9, 0.95, 10);
    NoiseCalibrationOptions o;
    o.windows_s = {0.5, 1, 2, 5, 10};
    const auto cal = hymm::datasets::calibrateOdometryNoise(run.commands, run.truth, o);
    EXPECT_NEAR(cal.bias.lag_s, 0.2, 0.021);
    EXPECT_NEAR(cal.bias.speed_scale, 0.9, 0.02);
    EXPECT_NEAR(cal.bias.speed_offset_mps, 0.0, 0.002);
    EXPECT_NEAR(cal.bias.turn_scale, 0.95, 0.01);
    EXPECT_LT(cal.bias.lag_heading_std_deg, cal.bias.turn_raw_std_deg);
    EXPECT_LT(cal.bias.turn_residual_std_deg, cal.bias.lag_heading_std_deg);
    // Systematic errors: the per-sample values inflate with the window length.
    EXPECT_GT(cal.per_window.back().std_speed_mps, 2 * cal.per_window.front().std_speed_mps);
}

TEST(NoiseCalibrationTest, ScaleErrorGrowsQuadraticallyNotLikeARandomWalk)
{
    const auto run = makeRun(600, 0.01, 1.0, 17, 1.0, 0.9);
    NoiseCalibrationOptions o;
    o.windows_s = {0.2, 0.5, 1};
    o.fit_min_window_s = 0.2;
    o.max_lag_s = 0.1;
    const auto cal = hymm::datasets::calibrateOdometryNoise(run.commands, run.truth, o);
    EXPECT_GT(cal.heading_growth_exponent, 1.6);
    EXPECT_NEAR(cal.bias.turn_scale, 0.9, 0.01);
    const auto white = makeRun(600, 0.01, 1.0, 17);
    EXPECT_NEAR(hymm::datasets::calibrateOdometryNoise(white.commands, white.truth, o)
                    .heading_growth_exponent,
                1.0, 0.15);
}

}  // namespace
