// Ground truth of moved objects on the chapter-6 scenarios (thesis Sec. 6.3.3).
#include <gtest/gtest.h>
#include <hymm/sim/Scenario.h>
#include <hymm/sim/Simulator.h>
#include <hymm/sim/motion_truth.h>

#include <cmath>
#include <map>
#include <string>

namespace
{
using namespace hymm::sim;
const std::string kDir = std::string(HYMM_SOURCE_DIR) + "/configs/sim/";

TEST(MotionTruth, SlowSceneHasThreeChangesAndTheMovedCar)
{
    Simulator sim(Scenario::fromFile(kDir + "ch6_dynamic_slow.ini"));
    const auto areas = changedAreas(sim.world(), 50.0, 150.0);
    std::map<std::string, std::string> got;
    for (const auto& a : areas) got[a.name + ":" + changeName(a.change)] = a.name;
    EXPECT_EQ(got.size(), 5u);
    EXPECT_TRUE(got.count("middle:removed"));
    EXPECT_TRUE(got.count("new_left:added"));
    EXPECT_TRUE(got.count("new_right:added"));
    EXPECT_TRUE(got.count("car:moved_from"));
    EXPECT_TRUE(got.count("car:moved_to"));
    for (const auto& a : areas)
        if (a.name == "car" && a.change == ChangedArea::Change::MovedTo)
        {
            double cx = 0;
            for (const auto& v : a.outline) cx += v.x() / static_cast<double>(a.outline.size());
            EXPECT_NEAR(cx, -2.0, 1e-6);
        }
    // Nothing changes before the change time, and the static objects never.
    EXPECT_TRUE(changedAreas(sim.world(), 10.0, 90.0).empty());
    EXPECT_EQ(staticOutlines(sim.world()).size(), 2u);  // west, east
}

TEST(MotionTruth, FastSceneSweepsTwoBandsAndTheSensorSeesTheirNearFaces)
{
    Simulator sim(Scenario::fromFile(kDir + "ch6_dynamic_fast.ini"));
    const auto fp = sweptFootprints(sim.world(), 0.0, 20.0, 0.1);
    EXPECT_EQ(fp.size(), 2u * 201u);
    for (const auto& poly : fp)
        for (const auto& v : poly) EXPECT_NEAR(std::abs(v.y()), 5.0, 0.5 + 1e-9);
    // Sensor at the origin facing east, 180 deg: every hit lies on a mover's outline
    // face towards the sensor (|y| = 4.5) or on its side faces.
    const auto hits = movingObjectHits(sim.world(), 5.0, Eigen::Vector3d::Zero(), M_PI,
                                       0.5 * M_PI / 180, 30.0);
    ASSERT_GT(hits.size(), 5u);
    for (const auto& h : hits)
    {
        EXPECT_GE(std::abs(h.y()), 4.5 - 1e-6);
        EXPECT_LE(std::abs(h.y()), 5.5 + 1e-6);
    }
    EXPECT_EQ(staticOutlines(sim.world()).size(), 3u);
}

}  // namespace
