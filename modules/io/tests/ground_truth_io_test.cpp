#include <gtest/gtest.h>
#include <hymm/io/ground_truth_io.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace
{
using namespace hymm::io;
namespace fs = std::filesystem;

// Scratch directory removed at the end of each test.
class GroundTruthIoTest : public ::testing::Test
{
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() /
               ("hymm_eval_gt_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string write(const std::string& name, const std::string& text)
    {
        const std::string p = (dir_ / name).string();
        std::ofstream(p) << text;
        return p;
    }

    fs::path dir_;
};

// Verbatim layout of MRPT 2.5.8 simul-landmarks output (CLandmarksMap::saveToTextFile and
// CMatrixDouble::saveToTextFile with a '%' header).
const char* kLandmarks =
    "  0.578229   7.694330   0.000000    5    0   0.000000 1 \n"
    "  7.054158   0.402772   0.000000    5    0   0.000000 2 \n"
    "  7.511504   7.787255   0.250000    5    0   0.000000 3 \n";
const char* kPath =
    "% Columns are: x(m) y(m) z(m) yaw(rad) pitch(rad) roll(rad)\n"
    "% File generated with mrpt-math at Mon Nov 23 12:37:07 2026\n"
    "\n"
    "%------------------------------------\n"
    "0.0000000000000000 0.0000000000000000 0.0000000000000000 0.0000000000000000 "
    "-0.0000000000000000 0.0000000000000000\n"
    "0.1992389410734177 0.0174311473965645 0.0000000000000000 0.0872664600610733 "
    "-0.0000000000000000 0.0000000000000000\n"
    "0.3962004933140447 0.0521607814081733 0.0000000000000000 0.1745329201221466 "
    "-0.0000000000000000 0.0000000000000000\n";

TEST_F(GroundTruthIoTest, ReadsSimulLandmarksFiles)
{
    const std::string rawlog = (dir_ / "demo.rawlog").string();
    write("demo.rawlog_ground_truth.txt", kLandmarks);
    write("demo.rawlog_ground_truth_robot_path.txt", kPath);
    const auto gt = loadSimulLandmarksGroundTruth(rawlog, 10.0, 0.5);
    EXPECT_FALSE(gt.path_has_timestamps);

    ASSERT_EQ(gt.landmarks.size(), 3u);
    EXPECT_EQ(gt.landmarks[0].id, 1);
    EXPECT_DOUBLE_EQ(gt.landmarks[0].x, 0.578229);
    EXPECT_DOUBLE_EQ(gt.landmarks[0].y, 7.694330);
    EXPECT_EQ(gt.landmarks[2].id, 3);
    ASSERT_EQ(gt.landmarks[2].extra.size(), 1u);
    EXPECT_DOUBLE_EQ(gt.landmarks[2].extra[0], 0.25);

    ASSERT_EQ(gt.path.size(), 3u);
    EXPECT_DOUBLE_EQ(gt.path[0].t, 10.0);
    EXPECT_DOUBLE_EQ(gt.path[2].t, 11.0);
    EXPECT_DOUBLE_EQ(gt.path[1].x, 0.1992389410734177);
    EXPECT_DOUBLE_EQ(gt.path[1].y, 0.0174311473965645);
    EXPECT_DOUBLE_EQ(gt.path[2].phi, 0.1745329201221466);
}

TEST_F(GroundTruthIoTest, MalformedSimulFilesNameTheLine)
{
    const std::string lm = write("bad_lm.txt", "  1.0 2.0 0.0 5 0\n");
    try
    {
        readSimulLandmarksLandmarks(lm);
        FAIL() << "no exception";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find(lm + ":1"), std::string::npos) << e.what();
    }
    const std::string path = write("bad_path.txt", "% header\n1 2 3 4 5 6\n1 2 x 4 5 6\n");
    try
    {
        readSimulLandmarksPath(path);
        FAIL() << "no exception";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find(path + ":3"), std::string::npos) << e.what();
    }
    EXPECT_THROW(readSimulLandmarksLandmarks((dir_ / "missing.txt").string()), std::runtime_error);
    EXPECT_THROW(readSimulLandmarksLandmarks(write("frac_id.txt", "1 2 0 5 0 0 1.5\n")),
                 std::runtime_error);
}

TEST_F(GroundTruthIoTest, ReadsHymmSimulatorFiles)
{
    const std::vector<hymm::io::StampedPose2D> path = {{0.0, 1, 2, 0.5}, {0.1, 1.5, 2.2, -3.0}};
    const std::vector<hymm::io::LandmarkRecord> lms = {{7, 3.5, -1, {0.3}}, {9, 4, 4, {0.2}}};
    const std::string tum = (dir_ / "gt.tum").string(), csv = (dir_ / "lm.csv").string();
    hymm::io::writeTum(tum, path);
    hymm::io::writeLandmarksCsv(csv, lms, "id,x,y,radius");
    const auto gt = loadHymmGroundTruth(tum, csv);
    EXPECT_TRUE(gt.path_has_timestamps);
    ASSERT_EQ(gt.path.size(), 2u);
    EXPECT_NEAR(gt.path[1].phi, -3.0, 1e-9);
    EXPECT_NEAR(gt.path[1].t, 0.1, 1e-12);
    ASSERT_EQ(gt.landmarks.size(), 2u);
    EXPECT_EQ(gt.landmarks[1].id, 9);
    EXPECT_NEAR(gt.landmarks[0].x, 3.5, 1e-12);
}

}  // namespace
