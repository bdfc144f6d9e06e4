// Noise calibration on synthetic runs the test generates: commands, true controls =
// commands + known per-sample noise (or systematic errors), the true path integrated
// from them, and landmark measurements with known noise and outliers.
#include <gtest/gtest.h>
#include <hymm/datasets/NoiseCalibration.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>

#include "test_files.h"

namespace
{
using hymm::io::StampedPose2D;
using hymm::datasets::LandmarkMeasurement;
using hymm::datasets::NoiseCalibrationOptions;
using Control = hymm::datasets::OdometryIntegrator::ControlSample;

constexpr double kDt = 0.02;

struct SyntheticRun
{
    std::vector<Control> commands;
    std::vector<StampedPose2D> truth;  // pose at each command time (before that sample)
};

/**
 * Piecewise-constant commands (segments of 1-6 s) at 50 Hz; the robot executes
 * speed_scale * v + noise and turn_scale * omega + noise of the command `delay`
 * samples earlier, each sample an arc step as the converter's unicycle model.
 */
SyntheticRun makeRun(double seconds, double std_v, double std_w_deg, unsigned seed,
                     double speed_scale = 1, double turn_scale = 1, int delay = 0)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> seg_len(50, 300), pick(0, 2);
    std::normal_distribution<double> n01(0, 1);
    SyntheticRun r;
    const auto n = static_cast<size_t>(seconds / kDt);
    double v = 0, w = 0;
    int left = 0;
    for (size_t i = 0; i < n; ++i)
    {
        if (left-- <= 0)
        {
            left = seg_len(rng);
            v = 0.1 * pick(rng);
            w = 0.4 * (pick(rng) - 1);
        }
        r.commands.push_back({static_cast<double>(i) * kDt, v, w});
    }
    double x = 0, y = 0, phi = 0;
    for (size_t i = 0; i < n; ++i)
    {
        r.truth.push_back({static_cast<double>(i) * kDt, x, y, phi});
        const Control& c = r.commands[i >= static_cast<size_t>(delay) ? i - delay : 0];
        const double cv = i >= static_cast<size_t>(delay) ? c.u0 : 0.0;
        const double cw = i >= static_cast<size_t>(delay) ? c.u1 : 0.0;
        const double tv = speed_scale * cv + std_v * n01(rng);
        const double tw = turn_scale * cw + mrpt::DEG2RAD(std_w_deg) * n01(rng);
        const double h = phi + 0.5 * tw * kDt;
        x += tv * kDt * std::cos(h);
        y += tv * kDt * std::sin(h);
        phi = mrpt::math::wrapToPi(phi + tw * kDt);
    }
    return r;
}

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

TEST(NoiseCalibrationTest, TruthGapsAndJumpsAreSkippedAndCounted)
{
    auto run = makeRun(600, 0.1, 10.0, 5);
    // A 3 s gap and one pose 1 m off (two jump steps).
    std::vector<StampedPose2D> truth;
    for (const auto& p : run.truth)
        if (p.t < 100 || p.t >= 103) truth.push_back(p);
    truth[20000].x += 1.0;
    NoiseCalibrationOptions o;
    o.windows_s = {1, 5};
    o.fit_min_window_s = 1;
    const auto cal = hymm::datasets::calibrateOdometryNoise(run.commands, truth, o);
    EXPECT_EQ(cal.truth_breaks, 3u);
    EXPECT_GE(cal.skipped.at("window_truth_break"), 3u);
    EXPECT_LE(cal.skipped.at("window_truth_break"), 6u);
    EXPECT_NEAR(cal.joint.std_speed_mps, 0.1, 0.01);
    EXPECT_NEAR(cal.joint.std_turn_rate_deg_s, 10.0, 1.0);

    auto bad = truth;
    bad[10].t = bad[9].t;  // not increasing
    EXPECT_THROW(hymm::datasets::calibrateOdometryNoise(run.commands, bad, o),
                 std::invalid_argument);
    o.windows_s = {1000};
    o.fit_min_window_s = 1000;
    EXPECT_THROW(hymm::datasets::calibrateOdometryNoise(run.commands, truth, o),
                 std::invalid_argument);
}

struct MeasurementSet
{
    std::vector<LandmarkMeasurement> meas;
    std::vector<hymm::io::LandmarkRecord> landmarks;
    size_t outliers = 0;
};

MeasurementSet makeMeasurements(const std::vector<StampedPose2D>& truth, double std_r,
                                double std_b_deg, double bias_r, double outlier_rate,
                                unsigned seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> n01(0, 1);
    std::uniform_real_distribution<double> u01(0, 1), off(-3, 3);
    std::uniform_int_distribution<size_t> along(0, truth.size() - 1);
    MeasurementSet s;
    for (long id = 6; id <= 20; ++id)  // near the path, so that each one is seen
    {
        const auto& p = truth[along(rng)];
        s.landmarks.push_back({id, p.x + off(rng), p.y + off(rng), {}});
    }
    for (size_t i = 0; i < truth.size(); i += 5)
    {
        const auto& p = truth[i];
        for (const auto& l : s.landmarks)
        {
            const double dx = l.x - p.x, dy = l.y - p.y, r = std::hypot(dx, dy);
            if (r > 6 || r < 0.3 || u01(rng) > 0.5) continue;
            LandmarkMeasurement m{p.t + 0.005, l.id, r + bias_r + std_r * n01(rng),
                                  mrpt::math::wrapToPi(std::atan2(dy, dx) - p.phi +
                                                       mrpt::DEG2RAD(std_b_deg) * n01(rng))};
            if (u01(rng) < outlier_rate) m.range += 2.0, ++s.outliers;
            s.meas.push_back(m);
        }
    }
    return s;
}

TEST(NoiseCalibrationTest, RangeAndBearingNoiseRobustToGrossOutliers)
{
    const auto run = makeRun(600, 0.1, 10.0, 9);
    auto set = makeMeasurements(run.truth, 0.05, 1.0, 0.03, 0.02, 4);
    ASSERT_GT(set.meas.size(), 5000u);
    ASSERT_GT(set.outliers, 50u);
    // Quirks: an unknown landmark, a time outside the track, a time inside a gap.
    set.meas.push_back({10.0, 99, 1.0, 0.0});
    set.meas.push_back({-5.0, 6, 1.0, 0.0});
    std::vector<StampedPose2D> truth;
    for (const auto& p : run.truth)
        if (p.t < 300 || p.t >= 301) truth.push_back(p);
    set.meas.push_back({300.5, 6, 1.0, 0.0});

    const auto cal = hymm::datasets::calibrateMeasurementNoise(set.meas, truth, set.landmarks,
                                                               NoiseCalibrationOptions{});
    EXPECT_EQ(cal.skipped.at("measurement_unknown_landmark"), 1u);
    EXPECT_EQ(cal.skipped.at("measurement_outside_truth"), 1u);
    EXPECT_GE(cal.skipped.at("measurement_truth_break"), 1u);
    EXPECT_NEAR(cal.range.median, 0.03, 0.005);
    EXPECT_NEAR(cal.range.mad_std, 0.05, 0.005);
    EXPECT_NEAR(cal.range.model_std, std::hypot(0.03, 0.05), 0.005);
    EXPECT_NEAR(cal.bearing.median, 0.0, 0.05);
    EXPECT_NEAR(cal.bearing.mad_std, 1.0, 0.1);
    // Every injected outlier (2 m = 40 std) is caught; few Gaussian ones are (5 std).
    EXPECT_GE(cal.range.outliers, set.outliers - cal.skipped.at("measurement_truth_break"));
    EXPECT_LE(cal.range.outliers, set.outliers + 5);
    EXPECT_NEAR(cal.range.inlier_std, 0.05, 0.005);
    for (const auto& [label, best] : cal.best_fit_landmark) EXPECT_EQ(best.first, label);
}

TEST(NoiseCalibrationTest, SwappedLabelsPointToTheLandmarksTheyFit)
{
    const auto run = makeRun(600, 0.1, 10.0, 13);
    auto set = makeMeasurements(run.truth, 0.05, 1.0, 0.0, 0.0, 8);
    for (auto& m : set.meas)  // the labels of 8 and 12 are swapped
        m.id = m.id == 8 ? 12 : (m.id == 12 ? 8 : m.id);
    const auto cal = hymm::datasets::calibrateMeasurementNoise(set.meas, run.truth, set.landmarks,
                                                               NoiseCalibrationOptions{});
    EXPECT_EQ(cal.best_fit_landmark.at(8).first, 12);
    EXPECT_EQ(cal.best_fit_landmark.at(12).first, 8);
    EXPECT_GT(cal.best_fit_landmark.at(8).second, 0.95);
    EXPECT_EQ(cal.best_fit_landmark.at(6).first, 6);
    EXPECT_GT(cal.outliers_by_landmark.at(8).second, cal.outliers_by_landmark.at(8).first / 2);
    EXPECT_LT(cal.outliers_by_landmark.at(6).second, 5u);
}

TEST(NoiseCalibrationTest, MrclamFilesCalibrateWithTheirQuirksCounted)
{
    using hymm::datasets::testing::TempDir;
    using hymm::datasets::testing::writeText;
    TempDir dir;
    const auto run = makeRun(300, 0.1, 10.0, 21);
    const auto set = makeMeasurements(run.truth, 0.05, 1.0, 0.0, 0.0, 2);
    std::ostringstream odo, gt, meas, bar, lm;
    odo << std::setprecision(10);
    gt << std::setprecision(10);
    for (const auto& c : run.commands) odo << c.t << " " << c.u0 << " " << c.u1 << "\n";
    for (size_t i = 0; i < run.truth.size(); ++i)
    {
        const auto& p = run.truth[i];
        gt << p.t << " " << p.x << " " << p.y << " " << p.phi << "\n";
        if (i == 1000) gt << p.t << " " << p.x << " " << p.y << " " << p.phi << "\n";  // duplicate
    }
    for (const auto& m : set.meas)
        meas << std::setprecision(10) << m.t << " " << 100 + m.id << " " << m.range << " "
             << m.bearing << "\n";
    bar << "1 5\n2 14\n3 41\n4 32\n5 23\n";
    for (const auto& l : set.landmarks)
    {
        bar << l.id << " " << 100 + l.id << "\n";
        lm << std::setprecision(10) << l.id << " " << l.x << " " << l.y << " 0.001 0.001\n";
    }
    writeText(dir.file("Robot2_Odometry.dat"), odo.str());
    writeText(dir.file("Robot2_Groundtruth.dat"), gt.str());
    writeText(dir.file("Robot2_Measurement.dat"), meas.str());
    writeText(dir.file("Barcodes.dat"), bar.str());
    writeText(dir.file("Landmark_Groundtruth.dat"), lm.str());
    writeText(dir.file("cal.ini"),
              "[MrclamImporter]\nrobot = 1\n[NoiseCalibration]\nwindows_s = 1 2 5\n"
              "fit_min_window_s = 1\n");

    const auto res = hymm::datasets::calibrateMrclam({dir.path()}, 2, dir.file("cal.ini"));
    EXPECT_EQ(res.reading.skippedCount("groundtruth_non_monotonic"), 1u);
    EXPECT_EQ(res.reading.odometry_samples, run.commands.size());
    EXPECT_NEAR(res.odometry.joint.std_speed_mps, 0.1, 0.01);
    EXPECT_NEAR(res.odometry.joint.std_turn_rate_deg_s, 10.0, 1.0);
    EXPECT_NEAR(res.measurements.range.mad_std, 0.05, 0.005);
    const std::string ini = res.iniLines();
    EXPECT_NE(ini.find("std_speed_mps = "), std::string::npos);
    EXPECT_NE(ini.find("std_bearing_deg = "), std::string::npos);
    EXPECT_NE(res.toString().find("robot 2"), std::string::npos);

    EXPECT_THROW(hymm::datasets::calibrateMrclam({dir.path()}, 9, ""), std::invalid_argument);
    writeText(dir.file("bad.ini"), "[NoiseCalibration]\nwindow_s = 1\n");
    EXPECT_THROW(hymm::datasets::calibrateMrclam({dir.path()}, 2, dir.file("bad.ini")),
                 std::invalid_argument);
    writeText(dir.file("bad2.ini"), "[NoiseCalibration]\nwindows_s = 1 2\nfit_min_window_s = 5\n");
    EXPECT_THROW(hymm::datasets::calibrateMrclam({dir.path()}, 2, dir.file("bad2.ini")),
                 std::invalid_argument);
}

}  // namespace
