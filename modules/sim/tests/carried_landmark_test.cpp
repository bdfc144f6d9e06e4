// A point landmark carried by an object (WorldObject::landmarks): it moves with the object,
// the detector reports it there, it vanishes with the object, and it is read, written
// back and checked like the other object keys.
#include <gtest/gtest.h>
#include <hymm/sim/LandmarkDetector.h>
#include <hymm/sim/World.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

namespace
{
using hymm::sim::Vec2;
using hymm::sim::World;

const char* kIni = R"([World]
landmarks = 5 5 0.2
[Object_car]
kind = car
shape = box
size = 4 2
trajectory = 0 10 0 0  10 20 0 90
disappear_s = 20
landmarks = 1 1.2 0.1
)";

World build(const std::string& ini)
{
    mrpt::config::CConfigFileMemory cfg(ini);
    World::Options o;
    o.loadFromConfigFile(cfg, "World");
    return World::build(o, nullptr);
}

TEST(CarriedLandmark, MovesWithItsObjectAndVanishesWithIt)
{
    const World w = build(kIni);
    ASSERT_EQ(w.landmarks().size(), 2u);
    const auto& lm = w.landmarks()[1];  // carried landmarks come after the others
    EXPECT_EQ(lm.id, 1);
    ASSERT_NE(w.carrier(lm), nullptr);
    EXPECT_EQ(w.carrier(lm)->name, "car");
    EXPECT_EQ(w.carrier(w.landmarks()[0]), nullptr);
    EXPECT_NEAR((lm.position - Vec2(11, 1.2)).norm(), 0, 1e-12);  // at the first pose
    auto carriedAt = [&](double t) {
        for (const auto& l : w.snapshot(t, Vec2(10, 0), 100).landmarks)
            if (l.id == 1) return std::optional<Vec2>(l.position);
        return std::optional<Vec2>();
    };
    EXPECT_NEAR((*carriedAt(0) - Vec2(11, 1.2)).norm(), 0, 1e-12);
    // At t = 10 the car is at (20, 0) turned 90 deg: (1, 1.2) -> (-1.2, 1).
    EXPECT_NEAR((*carriedAt(10) - Vec2(18.8, 1)).norm(), 0, 1e-12);
    EXPECT_FALSE(carriedAt(20).has_value());

    // The detector (known ids, no noise) reports it where the car is.
    hymm::sim::LandmarkDetector::Options d;
    d.known_ids = true;
    d.std_range_m = 0;
    d.std_bearing = 0;
    d.fov = 2 * M_PI;
    d.max_range_m = 50;
    hymm::sim::LandmarkDetector det(d, 1);
    const auto obs = det.observe(w, Eigen::Vector3d(18.8, -9, M_PI / 2), 10, mrpt::Clock::now());
    bool seen = false;
    for (const auto& m : obs->sensedData)
        if (m.landmarkID == 1)
        {
            seen = true;
            EXPECT_NEAR(m.range, 10.0, 1e-5);
            EXPECT_NEAR(m.yaw, 0.0, 1e-5);
        }
    EXPECT_TRUE(seen);
}

TEST(CarriedLandmark, RoundTripsAndBadValuesNameTheKey)
{
    mrpt::config::CConfigFileMemory cfg(kIni);
    World::Options o;
    o.loadFromConfigFile(cfg, "World");
    mrpt::config::CConfigFileMemory out;
    o.saveToConfigFile(out, "World");
    World::Options back;
    back.loadFromConfigFile(out, "World");
    ASSERT_EQ(back.objects.size(), 1u);
    ASSERT_EQ(back.objects[0].landmarks.size(), 1u);
    EXPECT_NEAR((back.objects[0].landmarks[0].offset - Vec2(1, 1.2)).norm(), 0, 1e-12);
    EXPECT_DOUBLE_EQ(back.objects[0].landmarks[0].radius, 0.1);

    std::string bad = kIni;
    bad.replace(bad.find("1 1.2 0.1"), 9, "1 1.2 -1");
    try
    {
        build(bad);
        FAIL() << "a negative radius was accepted";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("landmarks"), std::string::npos) << e.what();
    }
    // A carrier that does not exist.
    hymm::sim::Landmark orphan{0, Vec2(0, 0), 0.2, 7, Vec2(0, 0)};
    EXPECT_THROW(World({orphan}, {}), std::invalid_argument);
}

}  // namespace
