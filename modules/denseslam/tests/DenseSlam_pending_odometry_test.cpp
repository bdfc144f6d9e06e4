// DenseSlam with [ScanOdometry]: the odometry increments are held until the next frame
// with a scan (where the alignment refines them) or with bearing-range readings, or
// flushOdometry(), composed exactly; odometry inside a frame comes before its scan.
#include <gtest/gtest.h>
#include <hymm/core/StrictConfigFile.h>
#include <hymm/denseslam/DenseSlam.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <cmath>
#include <optional>

namespace
{
using hymm::denseslam::DenseSlam;

DenseSlam withScanOdometry()
{
    const auto cfg = hymm::core::StrictConfigFile::fromText(
        "[DenseSlam]\nlandmark_source = bearing_range\n[ScanOdometry]\nenabled = true\n", "pending odometry test");
    std::optional<DenseSlam> slam;
    cfg.load([&](const mrpt::config::CConfigFileBase& c) { slam.emplace(DenseSlam::fromConfig(c)); });
    return std::move(*slam);
}
}  // namespace

TEST(DenseSlamScanOdometry, PendingOdometryIsAppliedByTheNextFrameOrByFlush)
{
    DenseSlam slam = withScanOdometry();
    mrpt::poses::CPosePDFGaussian inc(mrpt::poses::CPose2D(1.0, 0.0, 0.1));
    inc.cov.setIdentity();
    inc.cov *= 0.01;
    slam.processOdometry(inc);
    slam.processOdometry(inc);
    // Deferred: the filter has not moved yet.
    EXPECT_EQ(slam.ekf().vehiclePose(), Eigen::Vector3d::Zero());
    slam.flushOdometry();
    // Both increments composed: 1 m, then 1 m after turning 0.1 rad.
    EXPECT_NEAR(slam.ekf().vehiclePose().x(), 1.0 + std::cos(0.1), 1e-9);
    EXPECT_NEAR(slam.ekf().vehiclePose().y(), std::sin(0.1), 1e-9);
    EXPECT_NEAR(slam.ekf().vehiclePose().z(), 0.2, 1e-9);
    // An empty frame leaves it pending; a frame of bearing-range readings (placed at the
    // pose) without a scan applies it as it is.
    slam.processOdometry(inc);
    slam.processFrame(mrpt::obs::CSensoryFrame());
    EXPECT_NEAR(slam.ekf().vehiclePose().z(), 0.2, 1e-9);
    mrpt::obs::CSensoryFrame beacons;
    beacons.insert(mrpt::obs::CObservationBearingRange::Create());
    slam.processFrame(beacons);
    EXPECT_NEAR(slam.ekf().vehiclePose().z(), 0.3, 1e-9);
    slam.flushOdometry();  // nothing pending: no change
    EXPECT_NEAR(slam.ekf().vehiclePose().z(), 0.3, 1e-9);
}

TEST(DenseSlamScanOdometry, OdometryInsideAFrameComesBeforeItsScanAndOtherReadingsWait)
{
    DenseSlam slam = withScanOdometry();
    const auto odometryAt = [](double x) {
        auto o = mrpt::obs::CObservationOdometry::Create();
        o->odometry = mrpt::poses::CPose2D(x, 0, 0);
        o->timestamp = mrpt::Clock::fromDouble(x);
        return o;
    };
    auto scan = mrpt::obs::CObservation2DRangeScan::Create();
    scan->aperture = static_cast<float>(M_PI);
    scan->maxRange = 30;
    scan->resizeScanAndAssign(181, 5.0f, true);
    mrpt::obs::CSensoryFrame first;
    first.insert(odometryAt(0));
    slam.processFrame(first);
    // The frame's odometry (1 m) and its scan: the scan is processed at the moved pose.
    mrpt::obs::CSensoryFrame second;
    second.insert(odometryAt(1));
    second.insert(scan);
    slam.processFrame(second);
    EXPECT_NEAR(slam.ekf().vehiclePose().x(), 1.0, 1e-9);
    EXPECT_EQ(slam.scanOdometry()->stats().scans, 1u);
    // A frame of a reading the pipeline does not place leaves the odometry pending.
    mrpt::poses::CPosePDFGaussian inc(mrpt::poses::CPose2D(0.5, 0.0, 0.0));
    inc.cov.setIdentity();
    inc.cov *= 0.01;
    slam.processOdometry(inc);
    mrpt::obs::CSensoryFrame imu;
    imu.insert(mrpt::obs::CObservationIMU::Create());
    slam.processFrame(imu);
    EXPECT_NEAR(slam.ekf().vehiclePose().x(), 1.0, 1e-9);
    slam.flushOdometry();
    EXPECT_NEAR(slam.ekf().vehiclePose().x(), 1.5, 1e-9);
}
