#include <gtest/gtest.h>
#include <hymm/core/config_utils.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/datasets/MrclamImporter.h>
#include <hymm/datasets/import_dataset.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "test_files.h"

namespace
{
using hymm::datasets::MrclamImporter;
using hymm::datasets::testing::TempDir;
using hymm::datasets::testing::writeText;

const char* kBarcodes =
    "# UTIAS Multi-Robot Cooperative Localization and Mapping Dataset\n"
    "# Subject #    Barcode #\n"
    "  1 \t   5 \n  2 \t  14 \n  5 \t  23 \n  6 \t  72 \n  7 \t  27 \n";

void writeDataset(const TempDir& dir)
{
    writeText(dir.file("Barcodes.dat"), kBarcodes);
    writeText(dir.file("Landmark_Groundtruth.dat"),
              "# Subject #    x [m]    y [m]    x std-dev [m]    y std-dev [m]\n"
              "  6 \t 1.5 \t 2.5 \t 0.001 \t 0.002 \n  7 \t -1.0 \t 0.5 \t 0.001 \t 0.001 \n");
    // 1 m/s, turning at 0.1 rad/s, 50 Hz for 4 s.
    std::ostringstream odo, gt;
    for (int i = 0; i <= 200; ++i)
    {
        odo << i * 0.02 << " 1 0.1\n";
        gt << i * 0.02 << " " << 0.02 * i << " 0 " << 0.002 * i << "\n";
    }
    writeText(dir.file("Robot1_Odometry.dat"), odo.str());
    writeText(dir.file("Robot1_Groundtruth.dat"), gt.str());
    writeText(dir.file("Robot1_Measurement.dat"),
              "1.00 72 2.0 0.5\n"    // landmark 6
              "1.00 27 3.0 -0.5\n"   // landmark 7, same time: same observation
              "1.00 14 1.0 0.0\n"    // robot 2: excluded
              "2.50 99 1.0 0.0\n"    // unknown barcode
              "3.00 5 1.0 0.0\n"     // robot 1 itself
              "3.00 72 2.5 0.25\n");
}

TEST(MrclamImporterTest, BarcodesMapToSubjectsAndRobotsAreExcluded)
{
    TempDir dir;
    writeDataset(dir);
    const auto codes = MrclamImporter::readBarcodes(dir.file("Barcodes.dat"));
    ASSERT_EQ(codes.size(), 5u);
    EXPECT_EQ(codes.at(72), 6);
    EXPECT_EQ(codes.at(14), 2);

    hymm::datasets::ImportSummary sum;
    const auto obs = MrclamImporter({}).readMeasurements(dir.file("Robot1_Measurement.dat"),
                                                         codes, sum);
    ASSERT_EQ(obs.size(), 2u);
    const auto& a = dynamic_cast<const mrpt::obs::CObservationBearingRange&>(*obs[0]);
    ASSERT_EQ(a.sensedData.size(), 2u);
    EXPECT_EQ(a.sensedData[0].landmarkID, 6);
    EXPECT_EQ(a.sensedData[1].landmarkID, 7);
    EXPECT_FLOAT_EQ(a.sensedData[1].yaw, -0.5f);
    EXPECT_FLOAT_EQ(a.sensedData[1].range, 3.0f);
    EXPECT_NEAR(mrpt::Clock::toDouble(a.timestamp), 1.0, 1e-6);
    const auto& b = dynamic_cast<const mrpt::obs::CObservationBearingRange&>(*obs[1]);
    ASSERT_EQ(b.sensedData.size(), 1u);
    EXPECT_EQ(b.sensedData[0].landmarkID, 6);
    EXPECT_EQ(sum.skippedCount("robot_barcode"), 2u);
    EXPECT_EQ(sum.skippedCount("unknown_barcode"), 1u);
    EXPECT_EQ(sum.measurements, 3u);
}

TEST(MrclamImporterTest, FullConversionWritesRawlogGroundTruthAndLandmarks)
{
    TempDir dir;
    writeDataset(dir);
    const auto sum = hymm::datasets::importDataset("mrclam", {dir.path()}, dir.file("out"));
    EXPECT_EQ(sum.frames, 2u);
    EXPECT_EQ(sum.odometry_samples, 201u);
    EXPECT_EQ(sum.ground_truth_poses, 201u);
    EXPECT_EQ(sum.landmarks, 2u);

    const auto log = hymm::datasets::testing::loadRawlog(dir.file("out/mrclam_robot1.rawlog"));
    ASSERT_EQ(log.size(), 4u);
    // Frame 0 integrates 0..1 s, frame 1 1..3 s of a 1 m/s, 0.1 rad/s arc.
    const auto mov = log.getAsAction(2)->getBestMovementEstimation();
    ASSERT_TRUE(mov);
    const double w = 0.1, T = 2.0;
    EXPECT_NEAR(mov->poseChange->getMeanVal().x(), std::sin(w * T) / w, 1e-4);
    EXPECT_NEAR(mov->poseChange->getMeanVal().y(), (1 - std::cos(w * T)) / w, 1e-4);
    EXPECT_NEAR(mov->poseChange->getMeanVal().phi(), w * T, 1e-9);

    const auto gt = hymm::io::readTum(dir.file("out/mrclam_robot1_groundtruth.tum"));
    ASSERT_EQ(gt.size(), 201u);
    EXPECT_NEAR(gt.back().phi, 0.4, 1e-9);
    const auto lms = hymm::io::readLandmarksCsv(dir.file("out/mrclam_robot1_landmarks.csv"));
    ASSERT_EQ(lms.size(), 2u);
    EXPECT_EQ(lms[0].id, 6);
    EXPECT_EQ(lms[0].extra, (std::vector<double>{0.001, 0.002}));
}

TEST(MrclamImporterTest, TimesPrintedWithFiveDigitsAreRebuiltFromTheSamplePeriod)
{
    TempDir dir;
    writeText(dir.file("Barcodes.dat"), kBarcodes);
    std::ostringstream odo;
    odo << std::setprecision(5);  // as the files: 1000.02 prints as 1000
    for (int i = 0; i < 10; ++i) odo << 999.96 + 0.02 * i << " 1 0\n";
    writeText(dir.file("Robot1_Odometry.dat"), odo.str());
    writeText(dir.file("Robot1_Measurement.dat"), "1000.1 72 2.0 0.5\n");
    const auto sum = hymm::datasets::importDataset("mrclam", {dir.path()}, dir.file("out"));
    EXPECT_EQ(sum.odometry_samples, 10u);
    EXPECT_EQ(sum.skippedCount("odometry_non_monotonic"), 0u);
    EXPECT_EQ(sum.repairedCount("odometry_time_rounding"), 6u);
    const auto log = hymm::datasets::testing::loadRawlog(dir.file("out/mrclam_robot1.rawlog"));
    ASSERT_EQ(log.size(), 2u);
    const auto mov = log.getAsAction(0)->getBestMovementEstimation();
    ASSERT_TRUE(mov);
    EXPECT_NEAR(mov->poseChange->getMeanVal().x(), 1000.1 - 999.96, 1e-6);  // 1 m/s
}

TEST(MrclamImporterTest, BadInputsThrowClearly)
{
    TempDir dir;
    writeText(dir.file("Barcodes.dat"), "1 5\n2 5\n");
    EXPECT_THROW(MrclamImporter::readBarcodes(dir.file("Barcodes.dat")), std::runtime_error);
    try
    {
        MrclamImporter::findInputs({dir.path()}, 3);
        FAIL() << "no exception";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("Robot3_Odometry.dat"), std::string::npos);
    }
}

}  // namespace

namespace
{
TEST(MrclamImporterTest, BarcodeFixesApplyOnlyToTheListedPairs)
{
    TempDir dir;
    writeDataset(dir);
    // 72 -> 6 and 27 -> 7 swapped; 14 is listed as robot 2, so "14:3:8" does not apply.
    writeText(dir.file("fix.ini"),
              "[MrclamImporter]\nbarcode_fixes = 72:6:7 27:7:6 14:3:8\n");
    const auto cfg = hymm::core::openConfigFile(dir.file("fix.ini"));
    MrclamImporter::Options o;
    o.loadFromConfigFile(*cfg, "MrclamImporter");
    ASSERT_EQ(o.barcode_fixes.size(), 3u);
    hymm::datasets::ImportSummary sum;
    const auto codes = MrclamImporter(o).barcodeMap(dir.file("Barcodes.dat"), sum);
    EXPECT_EQ(codes.at(72), 7);
    EXPECT_EQ(codes.at(27), 6);
    EXPECT_EQ(codes.at(14), 2);
    EXPECT_EQ(sum.repairedCount("barcode_subject_fix"), 2u);

    const auto out = hymm::datasets::importDataset("mrclam", {dir.path()}, dir.file("out"),
                                                   dir.file("fix.ini"));
    EXPECT_EQ(out.repairedCount("barcode_subject_fix"), 2u);
    const auto log = hymm::datasets::testing::loadRawlog(dir.file("out/mrclam_robot1.rawlog"));
    const auto obs = log.getAsObservations(1)->getObservationByClass<
        mrpt::obs::CObservationBearingRange>();
    ASSERT_TRUE(obs);
    EXPECT_EQ(obs->sensedData[0].landmarkID, 7);  // barcode 72, listed as 6

    for (const char* bad : {"72:6", "72:6:x", "72-6-7", "72:6:7:1"})
    {
        writeText(dir.file("bad.ini"), std::string("[MrclamImporter]\nbarcode_fixes = ") + bad + "\n");
        EXPECT_THROW(o.loadFromConfigFile(*hymm::core::openConfigFile(dir.file("bad.ini")),
                                          "MrclamImporter"),
                     std::invalid_argument)
            << bad;
    }
}
// Text-input faults: each is an error naming the file and the line, and leaves no output.
void expectImportError(const TempDir& dir, const std::string& file, const std::vector<std::string>& parts)
{
    try
    {
        hymm::datasets::importDataset("mrclam", {dir.path()}, dir.file("out"));
        FAIL() << "imported without an error";
    }
    catch (const std::runtime_error& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find(dir.file(file)), std::string::npos) << m;
        for (const auto& p : parts) EXPECT_NE(m.find(p), std::string::npos) << m;
    }
    EXPECT_TRUE(!std::filesystem::exists(dir.file("out")) || std::filesystem::is_empty(dir.file("out")));
}

TEST(MrclamImporterTest, EmptyOdometryFileIsAnError)
{
    TempDir dir;
    writeDataset(dir);
    writeText(dir.file("Robot1_Odometry.dat"), "# Time [s]    v [m/s]    w [rad/s]\n");
    expectImportError(dir, "Robot1_Odometry.dat", {"no odometry line"});
}

TEST(MrclamImporterTest, OneMalformedTimeIsAnErrorNamingItsLine)
{
    // Line 51's time lost its decimal point: every later sample would have been dropped
    // as non-monotonic.
    TempDir dir;
    writeDataset(dir);
    std::ostringstream odo;
    for (int i = 0; i <= 200; ++i) odo << (i == 50 ? std::string("100") : std::to_string(i * 0.02)) << " 1 0.1\n";
    writeText(dir.file("Robot1_Odometry.dat"), odo.str());
    expectImportError(dir, "Robot1_Odometry.dat", {"line 51:", "odometry time 100"});
}

TEST(MrclamImporterTest, NegativeTimeIsAnErrorNamingItsLine)
{
    TempDir dir;
    writeDataset(dir);
    writeText(dir.file("Robot1_Measurement.dat"), "1.00 72 2.0 0.5\n-3.5 27 3.0 -0.5\n");
    expectImportError(dir, "Robot1_Measurement.dat", {"line 2:", "time -3.5 is negative"});
}

TEST(MrclamImporterTest, NonFiniteLandmarkIsAnErrorNamingItsLine)
{
    TempDir dir;
    writeDataset(dir);
    writeText(dir.file("Landmark_Groundtruth.dat"),
              "# Subject #    x [m]    y [m]    x std-dev [m]    y std-dev [m]\n"
              "  6 \t nan \t 2.5 \t 0.001 \t 0.002 \n  7 \t -1.0 \t 0.5 \t 0.001 \t 0.001 \n");
    expectImportError(dir, "Landmark_Groundtruth.dat", {"line 2:", "landmark 6 has a non-finite x"});
}
}  // namespace
