#include <gtest/gtest.h>
#include <hymm/io/OdometryRawlogWriter.h>
#include <hymm/datasets/ImportSummary.h>
#include <hymm/datasets/RawlogWriter.h>
#include <hymm/datasets/ground_truth.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include "test_files.h"

namespace
{
using hymm::datasets::OdometryIntegrator;
using hymm::datasets::testing::TempDir;

mrpt::obs::CObservation::Ptr landmarkObs(double t, float range)
{
    auto o = mrpt::obs::CObservationBearingRange::Create();
    o->timestamp = mrpt::Clock::fromDouble(t);
    mrpt::obs::CObservationBearingRange::TMeasurement m;
    m.range = range;
    m.yaw = 0.25f;
    m.pitch = 0;
    m.landmarkID = 7;
    o->sensedData.push_back(m);
    return o;
}

TEST(RawlogWriterTest, FramesReadBackThroughCRawlogWithClassesAndTimestamps)
{
    TempDir dir;
    // 1 m/s straight ahead from t = 100 s, 20 Hz.
    std::vector<OdometryIntegrator::ControlSample> s;
    for (int i = 0; i <= 200; ++i) s.push_back({100.0 + 0.05 * i, 1.0, 0.0});
    const OdometryIntegrator odo(OdometryIntegrator::Model::Unicycle, {}, {}, s);
    const std::vector<double> times = {100.5, 101.25, 103.0};
    std::vector<mrpt::obs::CObservation::Ptr> obs;
    for (double t : times) obs.push_back(landmarkObs(t, 4.0f));

    hymm::datasets::ImportSummary sum;
    hymm::datasets::writeOdometryRawlog(dir.file("a.rawlog"), odo, obs, sum);
    EXPECT_EQ(sum.frames, 3u);
    EXPECT_DOUBLE_EQ(sum.first_time_s, 100.5);
    EXPECT_DOUBLE_EQ(sum.last_time_s, 103.0);

    const auto log = hymm::datasets::testing::loadRawlog(dir.file("a.rawlog"));
    ASSERT_EQ(log.size(), 6u);
    double t_prev = 100.0;  // the first control: origin of the odometry
    for (size_t k = 0; k < 3; ++k)
    {
        ASSERT_EQ(log.getType(2 * k), mrpt::obs::CRawlog::etActionCollection);
        ASSERT_EQ(log.getType(2 * k + 1), mrpt::obs::CRawlog::etSensoryFrame);
        const auto mov = log.getAsAction(2 * k)->getBestMovementEstimation();
        ASSERT_TRUE(mov);
        const auto* g = dynamic_cast<const mrpt::poses::CPosePDFGaussian*>(mov->poseChange.get());
        ASSERT_NE(g, nullptr);
        EXPECT_NEAR(g->mean.x(), times[k] - t_prev, 1e-9);
        EXPECT_GT(g->cov(0, 0), 0.0);
        EXPECT_NEAR(mrpt::Clock::toDouble(mov->timestamp), times[k], 1e-6);
        const auto sf = log.getAsObservations(2 * k + 1);
        ASSERT_EQ(sf->size(), 1u);
        const auto o = sf->getObservationByClass<mrpt::obs::CObservationBearingRange>();
        ASSERT_TRUE(o);
        EXPECT_NEAR(mrpt::Clock::toDouble(o->timestamp), times[k], 1e-6);
        EXPECT_EQ(o->sensedData.at(0).landmarkID, 7);
        t_prev = times[k];
    }

    // The dead-reckoning path recomposes the increments.
    const auto path = hymm::datasets::deadReckoningFromRawlog(dir.file("a.rawlog"));
    ASSERT_EQ(path.size(), 3u);
    EXPECT_NEAR(path.back().x, 3.0, 1e-9);
    EXPECT_NEAR(path.back().t, 103.0, 1e-6);
}

TEST(RawlogWriterTest, UnsortedObservationsAndUnwritablePathsThrow)
{
    TempDir dir;
    const OdometryIntegrator odo(OdometryIntegrator::Model::Unicycle, {}, {}, {});
    hymm::datasets::ImportSummary sum;
    EXPECT_THROW(hymm::datasets::writeOdometryRawlog(dir.file("b.rawlog"), odo,
                                                     {landmarkObs(2, 1), landmarkObs(1, 1)}, sum),
                 std::invalid_argument);
    EXPECT_THROW(hymm::io::OdometryRawlogWriter(dir.file("no/such/dir/c.rawlog")),
                 std::runtime_error);
}

}  // namespace
