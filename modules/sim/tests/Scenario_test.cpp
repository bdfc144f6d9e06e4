#include <gtest/gtest.h>
#include <hymm/sim/Scenario.h>
#include <hymm/sim/Simulator.h>
#include <mrpt/system/filesystem.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "test_scenarios.h"

namespace
{
using hymm::sim::testing::loadScenario;
using hymm::sim::testing::Override;

/** The message of the std::invalid_argument that loading with `o` throws ("" if none). */
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

TEST(ScenarioTest, MissingFileIsAnError)
{
    try
    {
        hymm::sim::Scenario::fromFile("/nonexistent/dir/scenario.ini");
        FAIL() << "no exception";
    }
    catch (const std::invalid_argument& e)
    {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/scenario.ini"), std::string::npos);
    }
}

TEST(ScenarioTest, BadValuesNameSectionKeyAndValue)
{
    EXPECT_NE(
        loadError({{"Vehicle", "speeed_mps", "3"}}).find("[Vehicle] unknown key 'speeed_mps'"),
        std::string::npos);
    EXPECT_NE(loadError({{"Vehicle", "speed_mps", "fast"}})
                  .find("[Vehicle] speed_mps=fast: not a number"),
              std::string::npos);
    EXPECT_NE(loadError({{"Vehicle", "std_speed_mps", "-0.1"}}).find("std_speed_mps"),
              std::string::npos);
    EXPECT_NE(loadError({{"LandmarkDetector", "std_bearing_deg", "-1"}})
                  .find("[LandmarkDetector] std_bearing_deg=-1: out of range, must be [0, 180]"),
              std::string::npos);
    // Absurd values are refused with the value as written, not accepted or truncated.
    EXPECT_NE(loadError({{"Scenario", "laps", "5000000000"}}).find("[Scenario] laps=5000000000: out of range"),
              std::string::npos);
    EXPECT_NE(loadError({{"LaserSimulator", "max_range_m", "1e308"}}).find("max_range_m=1e308: out of range"),
              std::string::npos);
    EXPECT_NE(loadError({{"World", "seed", "-4"}}).find("[World] seed=-4: out of range"), std::string::npos);
    EXPECT_NE(loadError({{"PathFollower", "waypoints", "0 0 1e300 5 3 3"}}).find("'1e300' out of range"),
              std::string::npos);
    EXPECT_NE(loadError({{"World", "landmarks", "1 2 0"}}).find("landmark radius must be > 0"),
              std::string::npos);
    EXPECT_NE(loadError({{"LaserSimulator", "std_range_m", "-0.01"}}).find("[LaserSimulator]"),
              std::string::npos);
    EXPECT_NE(loadError({{"Sensor", "x", "1"}}).find("unknown section [Sensor]"),
              std::string::npos);
    EXPECT_NE(loadError({{"LaserSimulator", "period_s", "0.03"}}).find("multiple of"),
              std::string::npos);
    EXPECT_NE(loadError({{"PathFollower", "waypoints", "0 0 1"}}).find("waypoints"),
              std::string::npos);
    EXPECT_NE(loadError({{"Object_x", "shape", "circle"}}).find("[Object_x] shape=circle"),
              std::string::npos);
    EXPECT_NE(loadError({{"Object_box", "colour", "red"}}).find("unknown key 'colour'"),
              std::string::npos);
    EXPECT_NE(loadError({{"Scenario", "name", "a/b"}}).find("[Scenario] name=a/b"),
              std::string::npos);
    EXPECT_NE(loadError({{"Vehicle", "max_steering_deg", "80"}}).find("too large"),
              std::string::npos);
    EXPECT_NE(loadError({{"LaserSimulator", "enabled", "false"},
                         {"LandmarkDetector", "enabled", "false"}})
                  .find("enable at least one sensor"),
              std::string::npos);
    EXPECT_EQ(loadError({}), "");
}

TEST(ScenarioTest, BadFileNamesTheFile)
{
    const std::string path = mrpt::system::getTempFileName() + ".ini";
    // An unknown key in a known section (a repeated section is an error of its own).
    std::string text = hymm::sim::testing::smallScenarioText();
    const auto at = text.find("[Vehicle]\n");
    ASSERT_NE(at, std::string::npos);
    text.insert(at + 10, "wheels = 4\n");
    std::ofstream(path) << text;
    try
    {
        hymm::sim::Scenario::fromFile(path);
        FAIL() << "no exception";
    }
    catch (const std::invalid_argument& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(path), std::string::npos) << msg;
        EXPECT_NE(msg.find("wheels"), std::string::npos) << msg;
    }
    mrpt::system::deleteFile(path);
}

TEST(ScenarioTest, EveryShippedConfigLoadsAndStarts)
{
    const std::filesystem::path dir = std::string(HYMM_SOURCE_DIR) + "/configs/sim";
    size_t n = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
    {
        if (entry.path().extension() != ".ini") continue;
        SCOPED_TRACE(entry.path().string());
        ++n;
        const auto s = hymm::sim::Scenario::fromFile(entry.path().string());
        EXPECT_EQ(s.run.name, entry.path().stem().string());  // outputs named after the file
        hymm::sim::Simulator sim(s);
        hymm::sim::SimFrame frame;
        for (int i = 0; i < 20; ++i) ASSERT_TRUE(sim.next(frame));
    }
    EXPECT_GE(n, 6u);
}

}  // namespace
