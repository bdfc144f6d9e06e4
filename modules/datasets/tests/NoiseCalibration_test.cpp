// Noise calibration on synthetic runs the test generates (noise_calibration_runs.h): gaps
// and jumps in the truth, landmark measurements with known noise and outliers, the MRCLAM
// files' quirks. The fits on long runs: NoiseCalibrationFit_test.cpp.
#include <gtest/gtest.h>
#include <hymm/datasets/NoiseCalibration.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>

#include "noise_calibration_runs.h"
#include "test_files.h"

namespace
{
using hymm::io::StampedPose2D;
using hymm::datasets::LandmarkMeasurement;
using hymm::datasets::NoiseCalibrationOptions;
using hymm::test::makeRun;

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
