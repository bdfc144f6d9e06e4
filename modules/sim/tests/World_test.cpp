#include <gtest/gtest.h>
#include <hymm/sim/ClosedPath.h>
#include <hymm/sim/Simulator.h>
#include <hymm/sim/World.h>
#include <hymm/sim/ground_truth_io.h>
#include <mrpt/system/filesystem.h>

#include <cmath>

#include "test_scenarios.h"

namespace
{
using hymm::sim::Vec2;
using hymm::sim::testing::loadScenario;

TEST(WorldObjectTest, PoseIsPiecewiseLinearAndHeldAtTheEnds)
{
    hymm::sim::WorldObject obj;
    obj.outline = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    obj.trajectory = {{0, 0, 0, 0}, {10, 10, 0, M_PI / 2}, {20, 10, 10, M_PI / 2}};
    EXPECT_TRUE(obj.moves());
    EXPECT_FALSE(obj.isStatic());
    EXPECT_TRUE(obj.poseAt(-5).isApprox(Eigen::Vector3d(0, 0, 0)));
    EXPECT_TRUE(obj.poseAt(5).isApprox(Eigen::Vector3d(5, 0, M_PI / 4)));
    EXPECT_TRUE(obj.poseAt(15).isApprox(Eigen::Vector3d(10, 5, M_PI / 2)));
    EXPECT_TRUE(obj.poseAt(99).isApprox(Eigen::Vector3d(10, 10, M_PI / 2)));
    const auto outline = obj.outlineAt(20);
    EXPECT_NEAR((outline[0] - Vec2(11, 9)).norm(), 0.0, 1e-12);  // (-1,-1) turned 90 deg
}

TEST(WorldTest, ObjectsFromIniWithPresenceAndShapes)
{
    const auto s = loadScenario({{"Object_bin", "shape", "polygon"},
                                 {"Object_bin", "vertices", "0 0  0 1  1 0"},  // clockwise
                                 {"Object_bin", "pose", "5 5 90"},
                                 {"Object_bin", "disappear_s", "30"}});
    const auto& objs = s.world.objects;
    ASSERT_EQ(objs.size(), 3u);  // bin, box, walker: in section-name order
    EXPECT_EQ(objs[0].name, "bin");
    EXPECT_GT(hymm::sim::signedArea(objs[0].outline), 0);  // made counter-clockwise
    EXPECT_TRUE(objs[0].presentAt(29.9));
    EXPECT_FALSE(objs[0].presentAt(30));
    EXPECT_EQ(objs[1].name, "box");
    EXPECT_TRUE(objs[1].isStatic());
    EXPECT_NEAR(hymm::sim::signedArea(objs[1].outline), 40.0, 1e-9);
    EXPECT_EQ(objs[2].name, "walker");
    EXPECT_TRUE(objs[2].moves());
}

TEST(WorldTest, GeneratedItemsKeepClearOfThePathAndEachOther)
{
    auto s =
        loadScenario({{"World", "object_spacing_m", "15"}, {"World", "object_size_max_m", "6"}});
    hymm::sim::Simulator sim(s);
    const auto& world = sim.world();
    const auto& path = *sim.follower().path();
    const auto& o = s.world;
    ASSERT_GT(world.landmarks().size(), 15u);
    ASSERT_GT(world.objects().size(), 4u);
    for (size_t i = 0; i < world.landmarks().size(); ++i)
    {
        const auto& lm = world.landmarks()[i];
        EXPECT_EQ(lm.id, static_cast<long>(i));
        EXPECT_GE(path.distanceTo(lm.position) - lm.radius, o.clearance_m);
        for (size_t j = 0; j < i; ++j)
            EXPECT_GE((world.landmarks()[j].position - lm.position).norm(),
                      o.landmark_separation_m);
    }
    for (const auto& obj : world.objects())
    {
        if (obj.kind != "generated") continue;
        EXPECT_GE(hymm::sim::boundaryDistance(obj.outlineAt(0), path.vertices()), o.clearance_m);
        for (const auto& lm : world.landmarks())
            EXPECT_GE(hymm::sim::pointPolygonDistance(lm.position, obj.outlineAt(0)), lm.radius);
    }
    // Same options, same world; the noise seed does not change it.
    s.run.seed = 99;
    hymm::sim::Simulator sim2(s);
    ASSERT_EQ(sim2.world().landmarks().size(), world.landmarks().size());
    EXPECT_TRUE(sim2.world().landmarks().back().position == world.landmarks().back().position);
}

TEST(GroundTruthIoTest, OutlinesRoundTripWithOneLinePerChange)
{
    const auto s = loadScenario({{"Object_bin", "shape", "box"},
                                 {"Object_bin", "size", "1 1"},
                                 {"Object_bin", "pose", "5 5 0"},
                                 {"Object_bin", "appear_s", "1"},
                                 {"Object_bin", "disappear_s", "2"}});
    hymm::sim::Simulator sim(s);
    std::vector<double> t, stamps;
    for (int i = 0; i < 30; ++i)
    {
        t.push_back(0.1 * i);
        stamps.push_back(100 + 0.1 * i);
    }
    const std::string file = mrpt::system::getTempFileName();
    hymm::sim::writeObjectOutlines(file, sim.world(), t, stamps);
    const auto recs = hymm::sim::readObjectOutlines(file);
    size_t bin = 0, box = 0, walker = 0;
    for (const auto& r : recs)
    {
        const auto& obj = sim.world().objects().at(static_cast<size_t>(r.id));
        ASSERT_EQ(r.outline.size(), obj.outline.size());
        EXPECT_NEAR((r.outline[0] - obj.outlineAt(r.t_from - 100)[0]).norm(), 0.0, 1e-9);
        if (obj.name == "bin")
        {
            ++bin;
            EXPECT_NEAR(r.t_from, 101.0, 1e-9);
            EXPECT_NEAR(r.t_to, 101.9, 1e-9);
        }
        box += obj.name == "box";
        walker += obj.name == "walker";
    }
    EXPECT_EQ(bin, 1u);
    EXPECT_EQ(box, 1u);
    EXPECT_EQ(walker, 30u);  // moves: a line per frame
    mrpt::system::deleteFile(file);
}

}  // namespace
