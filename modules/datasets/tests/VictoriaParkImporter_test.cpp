#include <gtest/gtest.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/datasets/MatFile.h>
#include <hymm/datasets/VictoriaParkImporter.h>
#include <hymm/datasets/import_dataset.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <cmath>
#include <fstream>

#include "test_files.h"

namespace
{
using hymm::datasets::VictoriaParkImporter;
using hymm::datasets::testing::TempDir;
using hymm::datasets::testing::writeText;

constexpr double kOffset = 20.967;  // detections base = .mat ms / 1000 - 20.967 s

/** aa3_dr.mat: 40 Hz from 21940 ms, constant speed/steering, `n` samples. */
void writeDr(const std::string& path, int n, double speed, double steering)
{
    Eigen::MatrixXd t(n, 1), v(n, 1), s(n, 1);
    for (int i = 0; i < n; ++i)
    {
        t(i) = 21940 + 25 * i;
        v(i) = speed;
        s(i) = steering;
    }
    hymm::datasets::writeMatFile(path, {{"time", t}, {"speed", v}, {"steering", s}});
}

TEST(VictoriaParkImporterTest, DetectionsLandInTheFramesOfTheMatTimeBase)
{
    TempDir dir;
    writeDr(dir.file("aa3_dr.mat"), 400, 2.0, 0.0);  // 21.940 .. 31.915 s, 2 m/s straight
    // Two scans in the shifted base: 2.000 s -> 22.967 s, 5.500 s -> 26.467 s.
    writeText(dir.file("measurements.dat"),
              "     2.000   10.0    1.5707963    0.30\n"
              "     2.000   20.0    0.0          0.20\n"
              "     5.500   30.0    3.1415926    0.40\n");
    const auto sum = VictoriaParkImporter({}).run(
        VictoriaParkImporter::findInputs({dir.path()}), dir.file("out"));
    EXPECT_EQ(sum.frames, 2u);
    EXPECT_EQ(sum.measurements, 3u);
    EXPECT_EQ(sum.odometry_samples, 400u);
    EXPECT_EQ(sum.skippedCount("gps_file_missing"), 1u);

    const auto log = hymm::datasets::testing::loadRawlog(dir.file("out/victoria_park.rawlog"));
    ASSERT_EQ(log.size(), 4u);
    const double t_first_odo = 21.940;
    const double t_frames[2] = {2.0 + kOffset, 5.5 + kOffset};
    double t_prev = t_first_odo;
    for (size_t k = 0; k < 2; ++k)
    {
        const auto mov = log.getAsAction(2 * k)->getBestMovementEstimation();
        ASSERT_TRUE(mov);
        // Straight line at 2 m/s: the increment measures the time between frames.
        EXPECT_NEAR(mov->poseChange->getMeanVal().x(), 2.0 * (t_frames[k] - t_prev), 1e-6);
        const auto o = log.getAsObservations(2 * k + 1)
                           ->getObservationByClass<mrpt::obs::CObservationBearingRange>();
        ASSERT_TRUE(o);
        EXPECT_NEAR(mrpt::Clock::toDouble(o->timestamp), t_frames[k], 1e-6);
        t_prev = t_frames[k];
    }
}

TEST(VictoriaParkImporterTest, BearingFromTheLaserRightBecomesMrptYaw)
{
    TempDir dir;
    writeText(dir.file("m.dat"),
              "1.0 10.0 1.5707963 0.3\n"   // straight ahead
              "1.0 10.0 0.0 0.2\n"         // the laser's right: -y
              "1.0 10.0 3.1415926 0.1\n");  // the laser's left: +y
    hymm::datasets::ImportSummary sum;
    std::vector<std::vector<double>> diam;
    VictoriaParkImporter::Options o;
    const auto obs = VictoriaParkImporter(o).readDetections(dir.file("m.dat"), sum, diam);
    ASSERT_EQ(obs.size(), 1u);
    const auto& br = dynamic_cast<const mrpt::obs::CObservationBearingRange&>(*obs[0]);
    ASSERT_EQ(br.sensedData.size(), 3u);
    for (size_t j = 0; j < 3; ++j)
    {
        const auto& m = br.sensedData[j];
        // Landmark in the laser frame, as MRPT would place it.
        const double x = m.range * std::cos(m.yaw), y = m.range * std::sin(m.yaw);
        const double ex[3] = {10, 0, 0}, ey[3] = {0, -10, 10};
        EXPECT_NEAR(x, ex[j], 1e-5);
        EXPECT_NEAR(y, ey[j], 1e-5);
        EXPECT_EQ(m.landmarkID, -1);
    }
    EXPECT_EQ(diam.at(0), (std::vector<double>{0.3, 0.2, 0.1}));
    EXPECT_EQ(br.sensorLocationOnRobot, mrpt::poses::CPose3D());  // robot frame = laser

    o.track_laser = false;  // odometry of the rear axle: the laser sits at (a, b)
    const auto obs2 = VictoriaParkImporter(o).readDetections(dir.file("m.dat"), sum, diam);
    const auto& br2 = dynamic_cast<const mrpt::obs::CObservationBearingRange&>(*obs2[0]);
    EXPECT_NEAR(br2.sensorLocationOnRobot.x(), 3.78, 1e-12);
    EXPECT_NEAR(br2.sensorLocationOnRobot.y(), 0.5, 1e-12);
}

TEST(VictoriaParkImporterTest, QuirksAreSkippedAndCounted)
{
    TempDir dir;
    writeText(dir.file("m.dat"),
              "1.0 10.0 1.0 0.3\n"
              "1.0 nan 1.0 0.3\n"      // NaN
              "1.0 95.0 1.0 0.3\n"     // beyond the laser's range
              "1.0 10.0 4.0 0.3\n"     // bearing outside 0..pi
              "0.5 10.0 1.0 0.3\n"     // time goes back
              "garbage line\n"
              "2.0 0.1 1.0 0.3\n"      // too close: the scan ends up empty
              "3.0 12.0 2.0 0.5\n");
    hymm::datasets::ImportSummary sum;
    std::vector<std::vector<double>> diam;
    const auto obs = VictoriaParkImporter({}).readDetections(dir.file("m.dat"), sum, diam);
    EXPECT_EQ(obs.size(), 2u);
    EXPECT_EQ(diam.size(), 2u);
    EXPECT_EQ(sum.measurements, 2u);
    EXPECT_EQ(sum.skippedCount("detection_nan"), 1u);
    EXPECT_EQ(sum.skippedCount("detection_out_of_range"), 2u);
    EXPECT_EQ(sum.skippedCount("detection_bad_bearing"), 1u);
    EXPECT_EQ(sum.skippedCount("detection_non_monotonic"), 1u);
    EXPECT_EQ(sum.skippedCount("detection_malformed_line"), 1u);
    EXPECT_EQ(sum.skippedCount("scan_without_valid_detections"), 1u);
}

TEST(VictoriaParkImporterTest, GpsIsWrittenOnTheRawlogBaseWithJumpsRemoved)
{
    TempDir dir;
    writeDr(dir.file("aa3_dr.mat"), 100, 1.0, 0.05);
    writeText(dir.file("measurements.dat"), "1.0 10.0 1.0 0.3\n");
    Eigen::MatrixXd t(5, 1), x(5, 1), y(5, 1);
    t << 20967, 21968, 22168, 22368, 22368;
    x << 0.0, 0.5, 90.0, 0.9, 1.0;  // a 90 m jump in 0.2 s, then a duplicated time
    y << 0.0, 0.1, 0.2, 0.3, 0.4;
    hymm::datasets::writeMatFile(dir.file("aa3_gpsx.mat"), {{"timeGps", t}, {"Lo_m", x}, {"La_m", y}});
    const auto sum = VictoriaParkImporter({}).run(
        VictoriaParkImporter::findInputs({dir.path()}), dir.file("out"));
    EXPECT_EQ(sum.skippedCount("gps_jump"), 1u);
    EXPECT_EQ(sum.skippedCount("gps_non_monotonic"), 1u);
    const auto gps = hymm::io::readTum(dir.file("out/victoria_park_gps.tum"));
    ASSERT_EQ(gps.size(), 3u);
    EXPECT_NEAR(gps[0].t, 20.967, 1e-9);
    EXPECT_NEAR(gps[2].t, 22.368, 1e-9);
    EXPECT_NEAR(gps[2].x, 0.9, 1e-9);
    // The diameters side file has one row per detection.
    std::ifstream f(dir.file("out/victoria_park_tree_diameters.csv"));
    std::string line, last;
    int rows = 0;
    while (std::getline(f, line))
        if (!line.empty() && line[0] != '#') ++rows, last = line;
    EXPECT_EQ(rows, 1);
    EXPECT_NE(last.find(",0.3"), std::string::npos);
}

TEST(VictoriaParkImporterTest, MissingOrCorruptInputGivesAClearError)
{
    TempDir dir;
    try
    {
        VictoriaParkImporter::findInputs({dir.path()});
        FAIL() << "no exception";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("aa3_dr.mat"), std::string::npos);
    }
    writeText(dir.file("aa3_dr.mat"), "not a mat file");
    writeText(dir.file("measurements.dat"), "1.0 10.0 1.0 0.3\n");
    EXPECT_THROW(VictoriaParkImporter({}).run(VictoriaParkImporter::findInputs({dir.path()}),
                                              dir.file("out")),
                 std::runtime_error);
    EXPECT_THROW(hymm::datasets::importDataset("nope", {dir.path()}, dir.file("out")),
                 std::invalid_argument);
}

TEST(VictoriaParkImporterTest, OptionsLoadStrictlyFromIni)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("VictoriaParkImporter", "a_m", 1.5);
    cfg.write("VictoriaParkImporter", "std_speed_mps", 0.3);
    VictoriaParkImporter::Options o;
    o.loadFromConfigFile(cfg, "VictoriaParkImporter");
    EXPECT_EQ(o.vehicle.a, 1.5);
    EXPECT_EQ(o.odometry.std_speed_mps, 0.3);
    cfg.write("VictoriaParkImporter", "a_mm", 1.5);  // typo
    EXPECT_THROW(o.loadFromConfigFile(cfg, "VictoriaParkImporter"), std::exception);
}

}  // namespace
