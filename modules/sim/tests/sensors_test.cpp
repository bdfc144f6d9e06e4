#include <gtest/gtest.h>
#include <hymm/core/RangeBearingModel.h>
#include <hymm/sim/LandmarkDetector.h>
#include <hymm/sim/LaserSimulator.h>
#include <hymm/sim/Simulator.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <vector>

#include "test_scenarios.h"

namespace
{
using hymm::sim::SimFrame;
using hymm::sim::testing::loadScenario;
using hymm::sim::testing::stdDev;

TEST(LandmarkDetectorTest, ResidualsMatchTheConfiguredSigmas)
{
    // Readings every 0.025 s over 3 laps, residuals against the exact geometry.
    const auto s = loadScenario({{"Scenario", "laps", "3"},
                                 {"LandmarkDetector", "period_s", "0.025"},
                                 {"LandmarkDetector", "pose_x_m", "0.5"},
                                 {"LandmarkDetector", "pose_yaw_deg", "10"},
                                 {"LaserSimulator", "enabled", "false"}});
    hymm::sim::Simulator sim(s);
    const auto& lms = sim.world().landmarks();
    std::vector<double> dr, db;
    SimFrame f;
    while (sim.next(f))
    {
        ASSERT_TRUE(f.detections);
        const auto& obs = *f.detections;
        EXPECT_EQ(obs.timestamp, f.stamp);
        EXPECT_FLOAT_EQ(obs.sensor_std_range, 0.15f);
        EXPECT_NEAR(obs.sensorLocationOnRobot.x(), 0.5, 1e-12);
        for (const auto& m : obs.sensedData)
        {
            ASSERT_GE(m.landmarkID, 0);  // known_ids = true
            const auto& lm = lms.at(static_cast<size_t>(m.landmarkID));
            const auto z =
                hymm::core::observeRangeBearing(f.true_pose, s.detector.mountPose(), lm.position);
            EXPECT_LE(z[0], s.detector.max_range_m);
            EXPECT_LE(std::abs(z[1]), s.detector.fov / 2);
            dr.push_back(m.range - z[0]);
            db.push_back(mrpt::math::wrapToPi(m.yaw - z[1]));
        }
    }
    ASSERT_GT(dr.size(), 10000u);
    double mean_r = 0, mean_b = 0;
    EXPECT_NEAR(stdDev(dr, &mean_r) / s.detector.std_range_m, 1.0, 0.03);
    EXPECT_NEAR(stdDev(db, &mean_b) / s.detector.std_bearing, 1.0, 0.03);
    EXPECT_NEAR(mean_r, 0.0, 0.01);
    EXPECT_NEAR(mean_b, 0.0, 0.001);
}

TEST(LandmarkDetectorTest, ReportsOnlyVisibleLandmarksInRangeAndView)
{
    // Parked at the origin facing +x: ahead, behind, too far, hidden behind a wall.
    auto s =
        loadScenario({{"PathFollower", "waypoints", "0 0"},
                      {"Vehicle", "speed_mps", "0"},
                      {"Scenario", "duration_s", "0.1"},
                      {"World", "landmarks", "5 0 0.2  -5 0 0.2  30 0 0.2  1 10 0.2  1 14 0.2"},
                      {"LandmarkDetector", "known_ids", "false"},
                      {"LandmarkDetector", "std_range_m", "0"},
                      {"LandmarkDetector", "std_bearing_deg", "0"},
                      {"Object_box", "pose", "0 12 0"},
                      {"Object_box", "size", "10 1"}});
    hymm::sim::Simulator sim(s);
    SimFrame f;
    ASSERT_TRUE(sim.next(f));
    std::vector<double> ranges;
    for (const auto& m : f.detections->sensedData)
    {
        EXPECT_EQ(m.landmarkID, -1);
        ranges.push_back(m.range);
    }
    // (5,0) ahead and (1,10) to the left; (-5,0) is behind, (30,0) beyond 20 m and
    // (1,14) behind the wall at y = 12.
    ASSERT_EQ(ranges.size(), 2u);
    EXPECT_NEAR(ranges[0], 5.0, 1e-6);
    EXPECT_NEAR(ranges[1], std::sqrt(101.0), 1e-6);

    s.detector.occlusion = false;
    hymm::sim::Simulator sim2(s);
    ASSERT_TRUE(sim2.next(f));
    EXPECT_EQ(f.detections->sensedData.size(), 3u);
}

TEST(LaserSimulatorTest, RangeResidualsMatchTheConfiguredSigma)
{
    const auto s = loadScenario({{"Scenario", "laps", "2"},
                                 {"LaserSimulator", "period_s", "0.05"},
                                 {"LandmarkDetector", "enabled", "false"},
                                 {"LaserSimulator", "pose_x_m", "-1"},
                                 {"LaserSimulator", "pose_yaw_deg", "5"}});
    hymm::sim::Simulator sim(s);
    std::vector<double> dr;
    size_t invalid = 0;
    SimFrame f;
    while (sim.next(f))
    {
        const auto& scan = *f.scan;
        ASSERT_EQ(scan.getScanSize(), 181u);
        EXPECT_EQ(scan.timestamp, f.stamp);
        const Eigen::Vector3d g = hymm::core::sensorGlobalPose(f.true_pose, s.laser.mountPose());
        const auto snap = sim.world().snapshot(f.t, g.head<2>(), s.laser.max_range_m);
        for (size_t i = 0; i < scan.getScanSize(); ++i)
        {
            const auto hit =
                snap.castRay(g.head<2>(), g[2] + scan.getScanAngle(i), s.laser.max_range_m);
            EXPECT_EQ(scan.getScanRangeValidity(i), hit.has_value());
            if (!hit)
            {
                ++invalid;
                continue;
            }
            // Away from the clamps at 0 and max range.
            if (hit->range > 1 && hit->range < s.laser.max_range_m - 1)
                dr.push_back(scan.getScanRange(i) - hit->range);
        }
    }
    ASSERT_GT(dr.size(), 10000u);
    EXPECT_GT(invalid, 1000u);  // open sky: no-return beams
    double mean = 0;
    EXPECT_NEAR(stdDev(dr, &mean) / s.laser.std_range_m, 1.0, 0.03);
    EXPECT_NEAR(mean, 0.0, 0.005);
}

TEST(LaserSimulatorTest, SeesAMovingObjectWhereItIsAtScanTime)
{
    // Parked at the origin facing +y (a 90 deg mount), a walker crosses at y = 5.
    const auto s = loadScenario({{"PathFollower", "waypoints", "0 0"},
                                 {"Vehicle", "speed_mps", "0"},
                                 {"Scenario", "duration_s", "20"},
                                 {"World", "landmark_spacing_m", "0"},
                                 {"LaserSimulator", "pose_yaw_deg", "90"},
                                 {"LaserSimulator", "std_range_m", "0"},
                                 {"Object_box", "pose", "0 -50 0"},
                                 {"Object_walker", "trajectory", "0 -10 5 0  20 10 5 0"}});
    hymm::sim::Simulator sim(s);
    SimFrame f;
    while (sim.next(f))
    {
        // The beam straight up (index 90) hits the walker only while it crosses x = 0.
        const double x_walker = -10 + f.t;
        const bool crossing = std::abs(x_walker) < 0.3;
        ASSERT_EQ(f.scan->getScanRangeValidity(90), crossing) << "t=" << f.t;
        if (crossing)
        {
            EXPECT_NEAR(f.scan->getScanRange(90), 4.7, 1e-5);
        }
    }
}

}  // namespace
