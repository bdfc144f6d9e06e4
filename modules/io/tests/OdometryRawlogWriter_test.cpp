/**
 * @file OdometryRawlogWriter_test.cpp
 * @brief The odometry covariance written into a rawlog is the one read back.
 */
#include "hymm/io/OdometryRawlogWriter.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <gtest/gtest.h>

namespace
{
// MRPT rebuilds the covariance of an emOdometry action from its own default motion
// model when reading it back; the writer must store the one propagated from the
// control noise.
TEST(OdometryRawlogWriterTest, CovarianceSurvivesTheRoundTrip)
{
    const std::string file = mrpt::system::getTempFileName() + ".rawlog";
    Eigen::Matrix3d cov;
    cov << 0.04, 0.002, 0.001, 0.002, 0.09, 0.003, 0.001, 0.003, 0.0012;
    const mrpt::poses::CPose2D inc(1.0, 0.1, 0.02);
    {
        hymm::io::OdometryRawlogWriter w(file);
        auto obs = mrpt::obs::CObservationOdometry::Create();
        obs->timestamp = mrpt::Clock::fromDouble(1.0);
        w.writeFrame(mrpt::Clock::fromDouble(1.0), inc, cov, {obs});
        w.close();
    }
    mrpt::io::CFileGZInputStream in(file);
    auto arch = mrpt::serialization::archiveFrom(in);
    mrpt::obs::CActionCollection::Ptr acts;
    arch >> acts;
    ASSERT_TRUE(acts);
    const auto mov = acts->getBestMovementEstimation();
    ASSERT_TRUE(mov);
    mrpt::poses::CPosePDFGaussian back;
    back.copyFrom(*mov->poseChange);
    EXPECT_NEAR(back.mean.x(), inc.x(), 1e-12);
    EXPECT_NEAR(back.mean.phi(), inc.phi(), 1e-12);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(back.cov(i, j), cov(i, j), 1e-15) << i << "," << j;
    mrpt::system::deleteFile(file);
}
}  // namespace
