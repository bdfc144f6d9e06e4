// HighLevelLandmarks (thesis 6.1): a template in its rectangle's frame, kept pending
// until the sensor sees it, initialised from that observation at the true pose of the
// rectangle's frame (the simulator knows the object), observed by alignment after,
// excluded as an area; nothing happens while it is out of view.
#include <gtest/gtest.h>
#include <hymm/hll/HighLevelLandmarks.h>
#include <hymm/scanslam/SogMatcher.h>
#include <hymm/sim/LaserSimulator.h>
#include <hymm/sim/World.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/Clock.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <iostream>
#include <string>

namespace
{
using namespace hymm::hll;
using hymm::scanslam::Vec3;

// A 6 x 3 m building whose corner (0, 0) of its frame is at (12, -1.5), yaw 0.2.
const Vec3 kObject(12, -1.5, 0.2);
const hymm::sim::Polygon kOutline = {{0, 0}, {6, 0}, {6, 3}, {0, 3}};

hymm::sim::World world()
{
    hymm::sim::WorldObject o;
    o.id = 0;
    o.name = "building";
    o.outline = kOutline;
    o.trajectory = {hymm::sim::PoseKey{0, kObject.x(), kObject.y(), kObject.z()}};
    return hymm::sim::World({}, {o});
}

Vec2 place(const Vec3& z, const Vec2& p)
{
    return {std::cos(z.z()) * p.x() - std::sin(z.z()) * p.y() + z.x(),
            std::sin(z.z()) * p.x() + std::cos(z.z()) * p.y() + z.y()};
}

/** The SOG layer's view of the building: Gaussians every 5 cm along its outline. */
std::vector<HllDetector::Gaussian> denseGaussians()
{
    std::vector<HllDetector::Gaussian> out;
    for (size_t e = 0; e < kOutline.size(); ++e)
    {
        const Vec2 a = kOutline[e];
        const Vec2 b = kOutline[(e + 1) % kOutline.size()];
        const int n = static_cast<int>(std::round((b - a).norm() / 0.05));
        for (int k = 0; k < n; ++k)
            out.push_back({place(kObject, a + (b - a) * (static_cast<double>(k) / n)),
                           0.01 * Eigen::Matrix2d::Identity()});
    }
    return out;
}

/** The rectangle of the pair of corners (0,0)-(0,3) of the building, 5 m margin. */
OrientedRect pairRect()
{
    HllDetector det(HllDetector::Options{});
    return det.pairRectangle(place(kObject, {0, 0}), place(kObject, {0, 3}));
}

mrpt::obs::CObservation2DRangeScan::Ptr scanFrom(const Vec3& pose, uint32_t seed)
{
    hymm::sim::LaserSimulator::Options o;
    o.max_range_m = 25;
    o.fov = M_PI;
    o.resolution = 0.5 * M_PI / 180;
    o.std_range_m = 0.05;
    o.std_bearing = 0.5 * M_PI / 180;
    hymm::sim::LaserSimulator sim(o, seed, seed + 1000);
    return sim.observe(world(), Eigen::Vector3d(pose.x(), pose.y(), pose.z()), 0.0, mrpt::Clock::now());
}

constexpr double kCovInflation = 4.0;

std::unique_ptr<HighLevelLandmarks> makeHll()
{
    HighLevelLandmarks::Options o;
    o.enabled = true;
    o.std_range_m = 0.05;
    o.std_bearing = 0.5 * M_PI / 180;
    // The SOG covariance of 5.4 is too small for independent scans of one object
    // (scanslam README: ~10 % of aligned observations outside the 99 % gate); the HLLs
    // use the measured inflation of configs/ch4_hll.ini.
    hymm::scanslam::SogMatcher::Options m;
    m.cov_inflation = kCovInflation;
    return std::make_unique<HighLevelLandmarks>(o, std::make_unique<hymm::scanslam::SogMatcher>(m));
}

hymm::ekf::EkfSlam makeEkf(const Vec3& pose)
{
    hymm::ekf::EkfSlam ekf{hymm::ekf::EkfSlam::Options{}};
    ekf.reset(pose, 1e-6 * Eigen::Matrix3d::Identity());
    return ekf;
}

TEST(HighLevelLandmarks, TemplateIsTheGaussiansInTheRectangleFrame)
{
    const OrientedRect r = pairRect();
    const auto g = denseGaussians();
    const auto tpl = HighLevelLandmarks::makeTemplate(r, g, 100000);
    EXPECT_EQ(tpl.sog.size(), countInside(r, g));
    // Eq. 6.1-6.4's HLL pose is the frame; every template point placed by it is a Gaussian.
    for (size_t i = 0; i < tpl.sog.size(); i += 17)
    {
        const Vec2 back = place(r.pose(), tpl.sog.points[i]);
        double best = 1e9;
        for (const auto& x : g) best = std::min(best, (x.mean - back).norm());
        EXPECT_LT(best, 1e-9);
        // Covariances rotate with the frame: isotropic stays isotropic.
        EXPECT_TRUE(tpl.sog.covs[i].isApprox(0.01 * Eigen::Matrix2d::Identity(), 1e-12));
    }
    // Thinning keeps an even stride over the whole area.
    const auto thin = HighLevelLandmarks::makeTemplate(r, g, 50);
    EXPECT_EQ(thin.sog.size(), 50u);
    double xmin = 1e9, xmax = -1e9;
    for (const Vec2& p : thin.sog.points) xmin = std::min(xmin, p.y()), xmax = std::max(xmax, p.y());
    EXPECT_GT(xmax - xmin, 2.5);  // spans the 3 m side, not one end of it
    OrientedRect far;
    far.centre = Vec2(100, 100);
    far.half = Vec2(1, 1);
    EXPECT_THROW(HighLevelLandmarks::makeTemplate(far, g, 10), std::invalid_argument);
}

TEST(HighLevelLandmarks, PendingUntilSeenThenInitialisedAtTheTrueFrameAndTracked)
{
    auto hll = makeHll();
    const OrientedRect r = pairRect();
    hll->addPending(r, HighLevelLandmarks::makeTemplate(r, denseGaussians(), 400), 999, 0.0);
    // Facing away: the building is behind the sensor, nothing is attempted.
    const Vec3 away(0, 0, M_PI);
    {
        auto ekf = makeEkf(away);
        hll->processScan(ekf, *scanFrom(away, 1), 1.0);
        EXPECT_EQ(hll->stats().init_attempts, 0u);
        EXPECT_EQ(ekf.numLandmarks(), 0u);
        EXPECT_EQ(hll->hlls()[0].landmark_id, -1);
    }

    // Facing it: initialised from this scan, at the rectangle frame's true pose.
    const Vec3 pose(0, 0, 0.1);
    auto ekf = makeEkf(pose);
    hll->processScan(ekf, *scanFrom(pose, 2), 2.0);
    ASSERT_EQ(hll->stats().initialised, 1u);
    const long id = hll->hlls()[0].landmark_id;
    ASSERT_TRUE(ekf.hasLandmark(id));
    const Vec3 est = ekf.landmarkBlockMean(id).head<3>();
    const Eigen::Matrix3d P = ekf.landmarkBlockCov(id).topLeftCorner<3, 3>();
    Vec3 e = est - r.pose();
    e.z() = std::remainder(e.z(), 2 * M_PI);
    EXPECT_LT(e.head<2>().norm(), 0.15);
    EXPECT_LT(std::abs(e.z()), 0.02);
    EXPECT_LT(e.dot(P.ldlt().solve(e)), 16.27);  // chi2(3) at 99.9 %
    EXPECT_EQ(hll->hlls()[0].t_initialised, 2.0);

    // From then on it is a scan landmark: observed by alignment, never initialised twice.
    for (uint32_t k = 0; k < 4; ++k) hll->processScan(ekf, *scanFrom(pose, 10 + k), 3.0 + k);
    EXPECT_EQ(hll->stats().initialised, 1u);
    EXPECT_GE(hll->tracker().stats().updated, 3u);
    EXPECT_LE(hll->tracker().stats().gated, 1u);
    EXPECT_EQ(hll->tracker().stats().created, 1u);
    EXPECT_TRUE(ekf.mean().allFinite());

    // Its area, at the estimate, excludes candidates that would duplicate it.
    const auto areas = hll->areas(ekf);
    ASSERT_EQ(areas.size(), 1u);
    EXPECT_TRUE(overlaps(areas[0], r));
    EXPECT_NEAR(areas[0].half.x(), r.half.x(), 1e-12);
}

TEST(HighLevelLandmarks, SearchIsDueEveryPeriodOfLogTime)
{
    auto hll = makeHll();
    EXPECT_FALSE(hll->due(100.0));  // the clock starts
    EXPECT_FALSE(hll->due(159.9));
    EXPECT_TRUE(hll->due(160.0));
    EXPECT_FALSE(hll->due(std::nan("")));
}

// [Laser] owns a laser return's noise: it sets the HLL templates' noise, and the section's
// own key for the same quantity is then an error naming it.
TEST(HighLevelLandmarks, LaserSectionSetsTheTemplateNoise)
{
    mrpt::config::CConfigFileMemory laser("[Laser]\nstd_range_m = 0.2\nstd_bearing_deg = 2\n");
    const auto o = HighLevelLandmarks::loadOptions(&laser);
    EXPECT_DOUBLE_EQ(o.std_range_m, 0.2);
    EXPECT_NEAR(o.std_bearing, 2 * M_PI / 180, 1e-15);
    mrpt::config::CConfigFileMemory own("[HighLevelLandmarks]\nstd_range_m = 0.3\n");
    EXPECT_DOUBLE_EQ(HighLevelLandmarks::loadOptions(&own).std_range_m, 0.3);  // deprecated, still read
    mrpt::config::CConfigFileMemory both("[HighLevelLandmarks]\nstd_range_m = 0.3\n[Laser]\nstd_range_m = 0.2\n");
    try
    {
        (void)HighLevelLandmarks::loadOptions(&both);
        ADD_FAILURE() << "both sections set the range noise";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("[HighLevelLandmarks] std_range_m"), std::string::npos) << e.what();
    }
}

}  // namespace
