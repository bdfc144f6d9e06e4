#include <gtest/gtest.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/datasets/CarParkImporter.h>
#include <hymm/datasets/MatFile.h>
#include <hymm/datasets/import_dataset.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <filesystem>

#include "test_files.h"

namespace
{
using hymm::datasets::CarParkImporter;
using hymm::datasets::testing::TempDir;

constexpr int kBeams = 361;

void writeCarPark(const TempDir& dir)
{
    const int n_dr = 200, n_scans = 3, n_gps = 4;
    Eigen::MatrixXd t(n_dr, 1), v(n_dr, 1), s(n_dr, 1);
    for (int i = 0; i < n_dr; ++i) t(i) = 45.0 + 0.025 * i, v(i) = 2.0, s(i) = 0.1;
    Eigen::MatrixXd tl(n_scans, 1), laser(n_scans, kBeams), inten(n_scans, kBeams);
    tl << 45.1, 45.3, 45.3;  // the last one repeats a time stamp
    laser.setConstant(5.0);
    laser(0, 10) = 81.9;   // no return
    laser(0, 11) = 81.91;  // no return (the file also has 81.87, 81.91)
    laser(1, 0) = NAN;
    inten.setZero();
    inten(0, 20) = 32768;
    Eigen::MatrixXd tg(n_gps, 1), gx(n_gps, 1), gy(n_gps, 1);
    tg << 45.0, 45.2, 45.4, 45.6;
    gx << 0, 0.4, 0.8, 1.2;
    gy << 0, 0, 0, 0;
    hymm::datasets::writeMatFile(
        dir.file("data_set.mat"),
        {{"Time_VS", t}, {"Velocity", v}, {"Steering", s}, {"TimeLaser", tl}, {"Laser", laser},
         {"Intensity", inten}, {"TimeGPS", tg}, {"GPSLon", gx}, {"GPSLat", gy}});
    Eigen::MatrixXd beac(2, 2);
    beac << 2.9, -4.0, 9.9, 6.9;
    hymm::datasets::writeMatFile(dir.file("beac_juan3.mat"), {{"estbeac", beac}});
}

TEST(CarParkImporterTest, ScansKeepIntensitiesAndMarkNoReturnsInvalid)
{
    TempDir dir;
    writeCarPark(dir);
    const auto sum =
        CarParkImporter({}).run(CarParkImporter::findInputs({dir.path()}), dir.file("out"));
    EXPECT_EQ(sum.frames, 2u);
    EXPECT_EQ(sum.skippedCount("scan_non_monotonic"), 1u);
    EXPECT_EQ(sum.skippedCount("beam_no_return_or_invalid"), 3u);
    EXPECT_EQ(sum.measurements, 2u * kBeams - 3u);
    EXPECT_EQ(sum.landmarks, 2u);
    EXPECT_EQ(sum.ground_truth_poses, 4u);

    const auto log = hymm::datasets::testing::loadRawlog(dir.file("out/carpark.rawlog"));
    ASSERT_EQ(log.size(), 4u);
    const auto scan = log.getAsObservations(1)
                          ->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
    ASSERT_TRUE(scan);
    ASSERT_EQ(scan->getScanSize(), static_cast<size_t>(kBeams));
    EXPECT_NEAR(scan->aperture, M_PI, 1e-6);
    EXPECT_TRUE(scan->rightToLeft);
    EXPECT_FALSE(scan->getScanRangeValidity(10));
    EXPECT_FALSE(scan->getScanRangeValidity(11));
    EXPECT_TRUE(scan->getScanRangeValidity(12));
    EXPECT_FLOAT_EQ(scan->getScanRange(12), 5.0f);
    ASSERT_TRUE(scan->hasIntensity());
    EXPECT_EQ(scan->getScanIntensity(20), 32768);
    EXPECT_NEAR(mrpt::Clock::toDouble(scan->timestamp), 45.1, 1e-6);
    EXPECT_EQ(scan->sensorPose, mrpt::poses::CPose3D());  // robot frame = laser

    const auto beacons = hymm::io::readLandmarksCsv(dir.file("out/carpark_beacons.csv"));
    ASSERT_EQ(beacons.size(), 2u);
    EXPECT_EQ(beacons[1].id, 2);
    EXPECT_DOUBLE_EQ(beacons[1].y, 6.9);
}

TEST(CarParkImporterTest, FailureOnALaterMatVariableLeavesNoCompleteLookingRawlog)
{
    // The beacons are read after the rawlog was written: a malformed estbeac must not
    // leave carpark.rawlog (nor anything else) in the output folder.
    TempDir dir;
    writeCarPark(dir);
    const auto ok = hymm::datasets::importDataset("carpark", {dir.path()}, dir.file("out"));
    ASSERT_FALSE(ok.outputs.empty());
    for (const auto& f : ok.outputs) EXPECT_TRUE(std::filesystem::exists(f)) << f;
    Eigen::MatrixXd beac(3, 3);  // neither N x 2 nor 2 x N
    beac.setZero();
    hymm::datasets::writeMatFile(dir.file("beac_juan3.mat"), {{"estbeac", beac}});
    try
    {
        hymm::datasets::importDataset("carpark", {dir.path()}, dir.file("out"));
        FAIL() << "a malformed estbeac was accepted";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("estbeac"), std::string::npos) << e.what();
    }
    // The earlier import's results were removed before the failed one started.
    ASSERT_TRUE(std::filesystem::is_directory(dir.file("out")));
    EXPECT_TRUE(std::filesystem::is_empty(dir.file("out")));
}

TEST(CarParkImporterTest, MismatchedLaserTableIsRejected)
{
    TempDir dir;
    Eigen::MatrixXd one(1, 1);
    one << 1.0;
    hymm::datasets::writeMatFile(dir.file("data_set.mat"),
                                 {{"Time_VS", one}, {"Velocity", one}, {"Steering", one},
                                  {"TimeLaser", Eigen::MatrixXd::Ones(2, 1)},
                                  {"Laser", Eigen::MatrixXd::Ones(3, kBeams)},
                                  {"Intensity", Eigen::MatrixXd::Zero(3, kBeams)}});
    EXPECT_THROW(
        CarParkImporter({}).run(CarParkImporter::findInputs({dir.path()}), dir.file("out")),
        std::runtime_error);
}

}  // namespace
