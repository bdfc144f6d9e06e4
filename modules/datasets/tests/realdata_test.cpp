// Converts the real datasets (folder from $HYMM_DATASETS) and checks the conversions.
#include <gtest/gtest.h>
#include <hymm/core/config_utils.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/datasets/NoiseCalibration.h>
#include <hymm/datasets/ground_truth.h>
#include <hymm/datasets/import_dataset.h>

#include <cmath>
#include <cstdlib>
#include <iostream>

#include "test_files.h"

namespace
{
using hymm::io::StampedPose2D;
using hymm::datasets::testing::TempDir;

std::string datasets()
{
    const char* d = std::getenv("HYMM_DATASETS");
    return d ? d : "";
}

/** Position of `path` at time t (linear interpolation; false outside its span). */
bool interpolate(const std::vector<StampedPose2D>& path, double t, double& x, double& y)
{
    if (path.empty() || t < path.front().t || t > path.back().t) return false;
    size_t i = 1;
    while (i < path.size() && path[i].t < t) ++i;
    if (i >= path.size()) i = path.size() - 1;
    const auto &a = path[i - 1], &b = path[i];
    const double s = b.t > a.t ? (t - a.t) / (b.t - a.t) : 0.0;
    x = a.x + s * (b.x - a.x);
    y = a.y + s * (b.y - a.y);
    return true;
}

/**
 * Mean distance between dead reckoning and GPS after aligning the start pose: the start
 * position on the first GPS fix, the heading from the direction of the first
 * `align_dist` metres travelled by both.
 */
double meanDrError(const std::vector<StampedPose2D>& dr, const std::vector<StampedPose2D>& gps,
                   double align_dist)
{
    double x0, y0;
    const double t0 = std::max(dr.front().t, gps.front().t);
    EXPECT_TRUE(interpolate(dr, t0, x0, y0));
    double gx0, gy0;
    EXPECT_TRUE(interpolate(gps, t0, gx0, gy0));
    double rot = 0;
    for (const auto& g : gps)
    {
        double dx, dy;
        if (g.t <= t0 || std::hypot(g.x - gx0, g.y - gy0) < align_dist ||
            !interpolate(dr, g.t, dx, dy))
            continue;
        rot = std::atan2(g.y - gy0, g.x - gx0) - std::atan2(dy - y0, dx - x0);
        break;
    }
    double sum = 0;
    size_t n = 0;
    for (const auto& g : gps)
    {
        double dx, dy;
        if (g.t < t0 || !interpolate(dr, g.t, dx, dy)) continue;
        const double c = std::cos(rot), s = std::sin(rot);
        const double ax = gx0 + c * (dx - x0) - s * (dy - y0);
        const double ay = gy0 + s * (dx - x0) + c * (dy - y0);
        sum += std::hypot(ax - g.x, ay - g.y);
        ++n;
    }
    return n ? sum / n : NAN;
}

TEST(RealDatasetsTest, VictoriaParkConvertsWithAllDetections)
{
    if (datasets().empty()) GTEST_SKIP() << "HYMM_DATASETS not set";
    TempDir out;
    const auto sum = hymm::datasets::importDataset(
        "victoria",
        {datasets() + "/victoria_park", datasets() + "/victoria_park_txt_rfsslam"}, out.path());
    std::cout << sum.toString();
    EXPECT_NEAR(static_cast<double>(sum.frames), 7230, 10);
    EXPECT_NEAR(static_cast<double>(sum.measurements), 52974, 100);
    EXPECT_GT(sum.odometry_samples, 61000u);
    EXPECT_GT(sum.ground_truth_poses, 4000u);
    const auto dr = hymm::datasets::deadReckoningFromRawlog(out.file("victoria_park.rawlog"));
    const auto gps = hymm::io::readTum(out.file("victoria_park_gps.tum"));
    const double err = meanDrError(dr, gps, 20.0);
    std::cout << "Victoria Park dead reckoning vs GPS, mean distance: " << err << " m\n";
    EXPECT_GT(err, 20.0);   // dead reckoning does drift
    EXPECT_LT(err, 300.0);  // but not wildly: the time base and the model are right
}

TEST(RealDatasetsTest, CarParkConvertsWithScansGpsAndBeacons)
{
    if (datasets().empty()) GTEST_SKIP() << "HYMM_DATASETS not set";
    TempDir out;
    const auto sum =
        hymm::datasets::importDataset("carpark", {datasets() + "/acfr_carpark"}, out.path());
    std::cout << sum.toString();
    EXPECT_NEAR(static_cast<double>(sum.frames), 586, 2);
    EXPECT_EQ(sum.landmarks, 15u);
    EXPECT_GT(sum.ground_truth_poses, 600u);
    const auto dr = hymm::datasets::deadReckoningFromRawlog(out.file("carpark.rawlog"));
    const auto gps = hymm::io::readTum(out.file("carpark_gps.tum"));
    const double err = meanDrError(dr, gps, 5.0);
    std::cout << "Car park dead reckoning vs GPS, mean distance: " << err << " m\n";
    EXPECT_LT(err, 30.0);
}

TEST(RealDatasetsTest, MrclamRobot1ConvertsWithIdentifiedLandmarks)
{
    if (datasets().empty()) GTEST_SKIP() << "HYMM_DATASETS not set";
    TempDir out;
    const auto sum = hymm::datasets::importDataset(
        "mrclam", {datasets() + "/utias_mrclam/MRCLAM_Dataset1"}, out.path());
    std::cout << sum.toString();
    EXPECT_EQ(sum.landmarks, 15u);
    EXPECT_GT(sum.frames, 1000u);
    EXPECT_GT(sum.skippedCount("robot_barcode"), 0u);
    // Every 50 Hz row is kept: times printed with 5 digits after 1000 s are rebuilt.
    EXPECT_EQ(sum.odometry_samples, 75000u);
    EXPECT_EQ(sum.repairedCount("odometry_time_rounding"), 20000u);
    const auto dr = hymm::datasets::deadReckoningFromRawlog(out.file("mrclam_robot1.rawlog"));
    auto gt = hymm::io::readTum(out.file("mrclam_robot1_groundtruth.tum"));
    const double err = meanDrError(dr, gt, 0.5);
    std::cout << "MRCLAM robot 1 dead reckoning vs Vicon, mean distance: " << err << " m\n";
    EXPECT_LT(err, 10.0);
}

// The noise values of configs/datasets/mrclam.ini are what hymm-calibrate gives on
// dataset 2, robot 1 (docs/results.md); dataset 1's label swap is found without the fix.
TEST(RealDatasetsTest, MrclamCalibrationReproducesTheConverterConfig)
{
    if (datasets().empty()) GTEST_SKIP() << "HYMM_DATASETS not set";
    const std::string ini = std::string(HYMM_SOURCE_DIR) + "/configs/datasets/mrclam.ini";
    const auto res = hymm::datasets::calibrateMrclam(
        {datasets() + "/utias_mrclam/MRCLAM_Dataset2"}, 1, ini);
    std::cout << res.toString();
    const auto cfg = hymm::core::openConfigFile(ini);
    const auto val = [&cfg](const char* key) {
        return hymm::core::readDouble(*cfg, "MrclamImporter", key, 0, true);
    };
    // The config holds the values rounded to 3 significant digits.
    EXPECT_NEAR(res.odometry.joint.std_speed_mps, val("std_speed_mps"), 0.005 * val("std_speed_mps"));
    EXPECT_NEAR(res.odometry.joint.std_turn_rate_deg_s, val("std_turn_rate_deg_s"),
                0.005 * val("std_turn_rate_deg_s"));
    EXPECT_NEAR(res.measurements.range.model_std, val("std_range_m"), 0.005 * val("std_range_m"));
    EXPECT_NEAR(res.measurements.bearing.model_std, val("std_bearing_deg"),
                0.005 * val("std_bearing_deg"));
    // The joint values predict the 5-20 s windows they were fitted on.
    EXPECT_NEAR(res.odometry.joint.mean_nees, 3.0, 0.2);
    EXPECT_NEAR(res.odometry.bias.lag_s, 0.2, 0.1);  // the commands lead the motion

    const auto d1 = hymm::datasets::calibrateMrclam(
        {datasets() + "/utias_mrclam/MRCLAM_Dataset1"}, 2, "");  // no barcode fixes
    EXPECT_EQ(d1.measurements.best_fit_landmark.at(11).first, 17);
    EXPECT_EQ(d1.measurements.best_fit_landmark.at(17).first, 11);
    const auto d1_fixed = hymm::datasets::calibrateMrclam(
        {datasets() + "/utias_mrclam/MRCLAM_Dataset1"}, 2, ini);
    for (const auto& [label, best] : d1_fixed.measurements.best_fit_landmark)
        EXPECT_EQ(best.first, label);
}

}  // namespace
