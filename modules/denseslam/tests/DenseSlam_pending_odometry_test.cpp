// DenseSlam with [ScanOdometry]: the odometry increments are held until the next frame
// (where the scan alignment refines them) or flushOdometry(), composed exactly.
#include <gtest/gtest.h>
#include <hymm/core/StrictConfigFile.h>
#include <hymm/denseslam/DenseSlam.h>
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
    // An empty frame (no scan) applies what is pending as it is.
    slam.processOdometry(inc);
    slam.processFrame(mrpt::obs::CSensoryFrame());
    EXPECT_NEAR(slam.ekf().vehiclePose().z(), 0.3, 1e-9);
    slam.flushOdometry();  // nothing pending: no change
    EXPECT_NEAR(slam.ekf().vehiclePose().z(), 0.3, 1e-9);
}
