// Small scenarios for the simulator tests, built from .ini text in memory.
#pragma once

#include <hymm/sim/Scenario.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <string>
#include <vector>

namespace hymm::sim::testing
{
/** A 60 x 20 m rounded loop (about 150 m) with landmarks along it, a box inside the
 *  loop and a moving object; laser and detector every 0.2 s. */
inline std::string smallScenarioText()
{
    return R"(
[Scenario]
name = small
seed = 7
laps = 1
[Vehicle]
speed_mps = 5
std_speed_mps = 0.3
std_steering_deg = 3
[PathFollower]
waypoints = 0 0  30 0  30 20  -30 20  -30 0
corner_radius_m = 6
lookahead_m = 6
[World]
landmark_spacing_m = 8
landmark_offset_min_m = 3
landmark_offset_max_m = 9
seed = 5
[LaserSimulator]
period_s = 0.2
resolution_deg = 1
max_range_m = 20
std_range_m = 0.1
[LandmarkDetector]
period_s = 0.2
max_range_m = 20
std_range_m = 0.15
std_bearing_deg = 1
known_ids = true
[Object_box]
kind = building
shape = box
size = 10 4
pose = 0 10 0
[Object_walker]
kind = person
shape = box
size = 0.6 0.6
trajectory = 0 -20 -6 0  20 20 -6 0
)";
}

/** One key set on top of the text: {section, key, value}. */
struct Override
{
    std::string section, key, value;
};

inline Scenario loadScenario(const std::vector<Override>& overrides = {},
                             const std::string& text = smallScenarioText())
{
    mrpt::config::CConfigFileMemory cfg(text);
    for (const auto& o : overrides) cfg.write(o.section, o.key, o.value);
    Scenario s;
    s.loadFromConfigFile(cfg);
    return s;
}

/** Sample standard deviation of `v`, and its mean in `mean` if given. */
inline double stdDev(const std::vector<double>& v, double* mean = nullptr)
{
    double m = 0, s = 0;
    for (double x : v) m += x;
    m /= static_cast<double>(v.size());
    for (double x : v) s += (x - m) * (x - m);
    if (mean) *mean = m;
    return std::sqrt(s / static_cast<double>(v.size() - 1));
}

}  // namespace hymm::sim::testing
