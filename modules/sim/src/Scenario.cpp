#include "hymm/sim/Scenario.h"

#include <hymm/core/StrictConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "config_text.h"

namespace hymm::sim
{
using hymm::core::throwConfigError;

namespace
{
const char* const kScenario = "Scenario";
const char* const kVehicle = "Vehicle";
const char* const kPath = "PathFollower";
const char* const kWorld = "World";
const char* const kLaser = "LaserSimulator";
const char* const kDetector = "LandmarkDetector";
const char* const kPlot = "WorldPlot";

/** Calls f(section, options) for each options struct of `s`, in file order. */
template <class S, class F>
void forEachSection(S& s, F&& f)
{
    f(kScenario, s.run);
    f(kVehicle, s.vehicle);
    f(kPath, s.path);
    f(kWorld, s.world);
    f(kLaser, s.laser);
    f(kDetector, s.detector);
    f(kPlot, s.plot);
}

void checkSections(const mrpt::config::CConfigFileBase& cfg)
{
    std::vector<std::string> sections, known;
    cfg.getAllSections(sections);
    Scenario probe;
    forEachSection(probe, [&](const char* name, const auto&) { known.push_back(name); });
    for (const auto& s : sections)
    {
        if (s.empty() || std::find(known.begin(), known.end(), s) != known.end()) continue;
        if (s.rfind(World::kObjectSectionPrefix, 0) == 0) continue;
        std::string list;
        for (const auto& k : known) list += " [" + k + "]";
        throw std::invalid_argument("unknown section [" + s + "] (known:" + list + " [" +
                                    World::kObjectSectionPrefix + "<name>])");
    }
}
}  // namespace

hymm::core::OptionTable Scenario::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.text("name", name, "base name of the output files", "letters, digits, `_`, `.`, `-`");
    t.integer("seed", seed, "", 0, 0xFFFFFFFFLL, "seed of the noise (the world has its own, [World] seed)");
    t.real("dt_s", dt_s, "s", above(0, 10), "dead-reckoning step (thesis: 0.025 s)");
    t.real("duration_s", duration_s, "s", between(0, 1e7), "run length; 0: drive `laps` laps");
    t.integer("laps", laps, "", 1, 10000, "laps of the loop when duration_s = 0");
    t.real("start_time_s", start_time_s, "s", between(0, 4e9),
           "timestamp of the first frame, seconds since 1970 (MRPT tools take 0 for no time)");
    return t;
}

void Scenario::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                           const std::string& s)
{
    table().load(cfg, s);
    if (name.empty() ||
        name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                               "0123456789_.-") != std::string::npos)
        throwConfigError(s, "name", name, "use letters, digits, '_', '.' or '-' (a file name)");
}

void Scenario::Options::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                         const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

long Scenario::stepsPerPeriod(double period_s) const
{
    return std::max(1L, std::lround(period_s / run.dt_s));
}

void Scenario::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg)
{
    checkSections(cfg);
    if (!cfg.sectionExists(kPath))
        throw std::invalid_argument(std::string("missing section [") + kPath +
                                    "] (the vehicle's waypoints)");
    forEachSection(*this, [&](const char* name, auto& o) { o.loadFromConfigFile(cfg, name); });

    // Combinations.
    if (!laser.enabled && !detector.enabled)
        throwConfigError(kLaser, "enabled", "false", "enable at least one sensor");
    for (const auto& [sec, opt] :
         {std::pair<const char*, const SensorOptions*>{kLaser, &laser}, {kDetector, &detector}})
    {
        const double k = opt->period_s / run.dt_s;
        if (opt->enabled && (k < 1 - 1e-9 || std::abs(k - std::round(k)) > 1e-6))
            throwConfigError(
                sec, "period_s", detail::formatNumber(opt->period_s),
                "must be a multiple of [Scenario] dt_s=" + detail::formatNumber(run.dt_s));
    }
    if (path.waypoints.size() == 1 && vehicle.speed_mps > 0)
        throwConfigError(kPath, "waypoints", "(1 point)",
                         "a single waypoint parks the vehicle: set [Vehicle] speed_mps=0 or give "
                         "a loop of at least 3 waypoints");
    if (run.duration_s <= 0 && vehicle.speed_mps <= 0)
        throwConfigError(kScenario, "duration_s", "0",
                         "a parked vehicle never completes a lap: set duration_s > 0");
}

void Scenario::saveToConfigFile(mrpt::config::CConfigFileBase& cfg) const
{
    forEachSection(*this, [&](const char* name, const auto& o) { o.saveToConfigFile(cfg, name); });
}

std::string Scenario::toIniText() const
{
    mrpt::config::CConfigFileMemory mem;
    saveToConfigFile(mem);
    std::string text;
    mem.getContent(text);
    return text;
}

Scenario Scenario::fromFile(const std::string& path)
{
    // Strict: empty, binary, duplicate and unknown sections are errors naming file and line.
    const hymm::core::StrictConfigFile file(path);
    Scenario s;
    try
    {
        file.load([&](const mrpt::config::CConfigFileBase& cfg) { s.loadFromConfigFile(cfg); });
        file.checkAllSectionsKnown();
    }
    catch (const hymm::core::ConfigError&)
    {
        throw;
    }
    catch (const std::exception& e)
    {
        throw std::invalid_argument("'" + path + "': " + e.what());
    }
    return s;
}

}  // namespace hymm::sim
