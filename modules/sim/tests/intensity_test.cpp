// Simulated surface properties (thesis Sec. 4.5: any scalar property of the
// environment) reported by the laser as intensities: each return carries the true
// property of what it hit plus the configured noise; off by default; ground truth file.
#include <gtest/gtest.h>
#include <hymm/core/RangeBearingModel.h>
#include <hymm/sim/Simulator.h>
#include <hymm/sim/ground_truth_io.h>
#include <hymm/sim/run_scenario.h>
#include <mrpt/system/filesystem.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "test_scenarios.h"

namespace
{
using hymm::sim::SimFrame;
using hymm::sim::Vec2;
using hymm::sim::testing::loadScenario;
using hymm::sim::testing::Override;
using hymm::sim::testing::stdDev;

// The small loop with an own value on the box and the landmarks, a wall that takes the
// smooth field, and noisy intensities; the walker has no value either (field).
std::vector<Override> propertyOverrides(double std_intensity)
{
    return {{"World", "landmark_property", "15"},
            {"World", "property_field", "50 0.5 -0.25"},
            {"Object_box", "property", "120"},
            {"Object_wall", "kind", "wall"},
            {"Object_wall", "shape", "box"},
            {"Object_wall", "size", "20 0.5"},
            {"Object_wall", "pose", "0 -12 0"},
            {"LaserSimulator", "intensity", "true"},
            {"LaserSimulator", "std_intensity", std::to_string(std_intensity)}};
}

std::string loadError(const std::vector<Override>& o)
{
    try
    {
        loadScenario(o);
    }
    catch (const std::invalid_argument& e)
    {
        return e.what();
    }
    return "";
}

TEST(LaserIntensityTest, IntensitiesAreTheSurfacePropertyWithinTheNoise)
{
    constexpr double kStd = 2.0;
    auto o = propertyOverrides(kStd);
    o.push_back({"Scenario", "laps", "2"});
    const auto s = loadScenario(o);
    hymm::sim::Simulator sim(s);
    const auto& world = sim.world();
    // Residuals per kind of surface: own value (box), landmarks, the field (wall).
    std::vector<double> own, landmarks, field;
    double field_lo = 1e9, field_hi = -1e9;
    SimFrame f;
    while (sim.next(f))
    {
        if (!f.scan) continue;
        const auto& scan = *f.scan;
        ASSERT_TRUE(scan.hasIntensity());
        const Eigen::Vector3d g = hymm::core::sensorGlobalPose(f.true_pose, s.laser.mountPose());
        const auto snap = world.snapshot(f.t, g.head<2>(), s.laser.max_range_m);
        for (size_t i = 0; i < scan.getScanSize(); ++i)
        {
            const double angle = g[2] + scan.getScanAngle(i);  // no bearing jitter here
            const auto hit = snap.castRay(g.head<2>(), angle, s.laser.max_range_m);
            ASSERT_EQ(scan.getScanRangeValidity(i), hit.has_value());
            if (!hit)
            {
                EXPECT_EQ(scan.getScanIntensity(i), 0);
                continue;
            }
            const Vec2 at = g.head<2>() + hit->range * Vec2(std::cos(angle), std::sin(angle));
            const double truth = world.propertyAt(*hit, at);
            const double residual = scan.getScanIntensity(i) - truth;
            if (hit->landmark)
            {
                EXPECT_EQ(truth, 15.0);
                landmarks.push_back(residual);
            }
            else if (world.objects().at(static_cast<size_t>(hit->id)).name == "box")
            {
                EXPECT_EQ(truth, 120.0);
                own.push_back(residual);
            }
            else if (world.objects().at(static_cast<size_t>(hit->id)).name == "wall")
            {
                EXPECT_NEAR(truth, 50 + 0.5 * at.x() - 0.25 * at.y(), 1e-9);
                field_lo = std::min(field_lo, truth);
                field_hi = std::max(field_hi, truth);
                field.push_back(residual);
            }
        }
    }
    // Gaussian noise then rounding to an integer: variance kStd^2 + 1/12.
    const double expected = std::sqrt(kStd * kStd + 1.0 / 12);
    for (const auto* v : {&own, &landmarks, &field})
    {
        ASSERT_GT(v->size(), 2000u);
        double mean = 0;
        EXPECT_NEAR(stdDev(*v, &mean) / expected, 1.0, 0.05);
        EXPECT_NEAR(mean, 0.0, 4 * expected / std::sqrt(static_cast<double>(v->size())));
    }
    EXPECT_GT(field_hi - field_lo, 5.0);  // the wall really samples a varying field
}

TEST(LaserIntensityTest, OffByDefaultAndRangesDoNotDependOnIt)
{
    auto o = propertyOverrides(0.0);
    o.push_back({"Scenario", "duration_s", "20"});
    o.push_back({"LaserSimulator", "std_bearing_deg", "0.5"});
    o.push_back({"LaserSimulator", "intensity", "false"});
    const auto s_off = loadScenario(o);
    o.back().value = "true";
    const auto s_on = loadScenario(o);
    hymm::sim::Simulator off(s_off), on(s_on);
    SimFrame a, b;
    size_t scans = 0, exact = 0;
    while (off.next(a))
    {
        ASSERT_TRUE(on.next(b));
        if (!a.scan) continue;
        ++scans;
        EXPECT_FALSE(a.scan->hasIntensity());
        ASSERT_TRUE(b.scan->hasIntensity());
        ASSERT_EQ(a.scan->getScanSize(), b.scan->getScanSize());
        for (size_t i = 0; i < a.scan->getScanSize(); ++i)
        {
            // The intensity noise has its own generator: ranges are the same bytes.
            ASSERT_EQ(a.scan->getScanRange(i), b.scan->getScanRange(i));
            ASSERT_EQ(a.scan->getScanRangeValidity(i), b.scan->getScanRangeValidity(i));
            const int v = b.scan->getScanIntensity(i);
            exact += v == 120 || v == 15;  // no noise: own values read exactly
        }
    }
    EXPECT_FALSE(on.next(b));
    EXPECT_GT(scans, 50u);
    EXPECT_GT(exact, 1000u);
}

TEST(LaserIntensityTest, PropertyKeysAreStrictAndWrittenBackOnlyWhenSet)
{
    const std::string plain = loadScenario().toIniText();
    for (const char* key : {"intensity", "property"})
        EXPECT_EQ(plain.find(key), std::string::npos) << key;

    const auto s = loadScenario(propertyOverrides(2.5));
    const std::string text = s.toIniText();
    for (const char* line : {"landmark_property = 15", "property_field = 50 0.5 -0.25",
                             "property = 120", "intensity = true", "std_intensity = 2.5"})
        EXPECT_NE(text.find(line), std::string::npos) << line << "\n" << text;
    mrpt::config::CConfigFileMemory cfg(text);
    hymm::sim::Scenario reloaded;
    reloaded.loadFromConfigFile(cfg);
    EXPECT_EQ(reloaded.toIniText(), text);

    EXPECT_NE(loadError({{"Object_box", "property", "shiny"}}).find("[Object_box] property=shiny"),
              std::string::npos);
    EXPECT_NE(loadError({{"Object_box", "property", "nan"}}).find("must be finite"),
              std::string::npos);
    EXPECT_NE(loadError({{"World", "property_field", "1 2"}}).find("[World] property_field"),
              std::string::npos);
    EXPECT_NE(loadError({{"World", "landmark_property", "inf"}}).find("landmark_property"),
              std::string::npos);
    EXPECT_NE(loadError({{"LaserSimulator", "std_intensity", "-1"}}).find("std_intensity"),
              std::string::npos);
    EXPECT_NE(loadError({{"LaserSimulator", "intensity", "maybe"}}).find("intensity"),
              std::string::npos);
}

TEST(LaserIntensityTest, GroundTruthPropertiesRoundTrip)
{
    const std::string dir = std::string(HYMM_BINARY_DIR) + "/test_out/sim_properties";
    mrpt::system::deleteFilesInDirectory(dir);
    mrpt::system::createDirectory(std::string(HYMM_BINARY_DIR) + "/test_out");
    mrpt::system::createDirectory(dir);

    auto o = propertyOverrides(1.0);
    o.push_back({"Scenario", "duration_s", "2"});
    const auto s = loadScenario(o);
    const auto sum = hymm::sim::runScenario(s, dir, false);
    const std::string file = dir + "/small_gt_properties.txt";
    ASSERT_EQ(sum.files.back(), file);
    const auto p = hymm::sim::readSurfaceProperties(file);
    hymm::sim::Simulator sim(s);
    const auto& truth = sim.world().properties();
    EXPECT_EQ(p.landmarks, truth.landmarks);
    EXPECT_EQ(p.objects, truth.objects);
    EXPECT_EQ(p.field.v0, 50);
    EXPECT_EQ(p.field.gx, 0.5);
    EXPECT_EQ(p.field.gy, -0.25);
    ASSERT_EQ(p.objects.size(), 1u);  // only the box has its own value
    EXPECT_EQ(sim.world().objects().at(static_cast<size_t>(p.objects.begin()->first)).name, "box");
    // The outlines file is unchanged by the property keys: the existing reader reads it.
    // (box and wall: one line each; the walker moves: one line per frame).
    EXPECT_EQ(hymm::sim::readObjectOutlines(dir + "/small_gt_objects.txt").size(), 2 + sum.frames);

    // Without intensities there is no property file.
    const auto plain = hymm::sim::runScenario(loadScenario({{"Scenario", "duration_s", "2"}}),
                                              dir + "/plain", false);
    for (const auto& f : plain.files) EXPECT_EQ(f.find("_gt_properties"), std::string::npos);

    const std::string bad = dir + "/bad.txt";
    std::ofstream(bad) << "field 1 2 3\nobject 4 5\nobject 4 6\n";
    EXPECT_THROW(hymm::sim::readSurfaceProperties(bad), std::runtime_error);
    std::ofstream(bad) << "colour 1\n";
    EXPECT_THROW(hymm::sim::readSurfaceProperties(bad), std::runtime_error);
    std::ofstream(bad) << "landmarks x\n";
    EXPECT_THROW(hymm::sim::readSurfaceProperties(bad), std::runtime_error);
}

}  // namespace
