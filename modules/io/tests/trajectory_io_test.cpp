#include <gtest/gtest.h>
#include <hymm/io/trajectory_io.h>
#include <mrpt/system/filesystem.h>

#include <cmath>
#include <fstream>

namespace
{
using namespace hymm::io;

TEST(TrajectoryIoTest, TumRoundTrip)
{
    const std::string path = mrpt::system::getTempFileName();
    std::vector<StampedPose2D> in{{0.0, 1.0, 2.0, 0.5}, {0.25, -3.0, 4.5, -3.0}, {1.0, 0, 0, 3.1}};
    writeTum(path, in);
    const auto out = readTum(path);
    ASSERT_EQ(out.size(), in.size());
    for (size_t i = 0; i < in.size(); ++i)
    {
        EXPECT_NEAR(out[i].t, in[i].t, 1e-9);
        EXPECT_NEAR(out[i].x, in[i].x, 1e-9);
        EXPECT_NEAR(out[i].y, in[i].y, 1e-9);
        EXPECT_NEAR(std::remainder(out[i].phi - in[i].phi, 2 * M_PI), 0.0, 1e-9);
    }
}

TEST(TrajectoryIoTest, EpochTimestampsKeepMicroseconds)
{
    const std::string path = mrpt::system::getTempFileName();
    writeTum(path, {{1764000000.123456, 1, 2, 0}, {1764000000.123457, 1, 2, 0}});
    const auto out = readTum(path);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_NEAR(out[0].t, 1764000000.123456, 2e-7);
    EXPECT_NEAR(out[1].t - out[0].t, 1e-6, 2e-7);
}

TEST(TrajectoryIoTest, MalformedTumLineIsAnError)
{
    const std::string path = mrpt::system::getTempFileName();
    std::ofstream(path) << "0 1 2 0 0 0 0 1\n1 nan 2 0 0 0 0 1\n";
    EXPECT_THROW(readTum(path), std::runtime_error);
    std::ofstream(path) << "0 1 2\n";
    EXPECT_THROW(readTum(path), std::runtime_error);
    EXPECT_THROW(readTum("/nonexistent/file.tum"), std::runtime_error);
}

TEST(TrajectoryIoTest, LandmarkCsvRoundTrip)
{
    const std::string path = mrpt::system::getTempFileName();
    writeLandmarksCsv(path, {{3, 1.5, -2.5, {0.3}}, {9, 4, 5, {}}}, "id,x,y,radius");
    const auto out = readLandmarksCsv(path);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].id, 3);
    EXPECT_DOUBLE_EQ(out[0].x, 1.5);
    ASSERT_EQ(out[0].extra.size(), 1u);
    EXPECT_DOUBLE_EQ(out[0].extra[0], 0.3);
    EXPECT_EQ(out[1].id, 9);
}

}  // namespace
