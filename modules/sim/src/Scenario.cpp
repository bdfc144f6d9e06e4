#include "hymm/sim/Scenario.h"

#include <hymm/core/StrictConfigFile.h>
#include <hymm/core/config_utils.h>
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

void Scenario::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                           const std::string& s)
{
    hymm::core::checkKnownKeys(cfg, s,
                               {"name", "seed", "dt_s", "duration_s", "laps", "start_time_s"});
    name = hymm::core::readString(cfg, s, "name", name);
    if (name.empty() ||
        name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                               "0123456789_.-") != std::string::npos)
        throwConfigError(s, "name", name, "use letters, digits, '_', '.' or '-' (a file name)");
    seed = hymm::core::readInt(cfg, s, "seed", seed);
    if (seed < 0 || seed > 0xFFFFFFFFL)
        throwConfigError(s, "seed", std::to_string(seed), "must be in [0, 2^32)");
    dt_s = hymm::core::readDoubleMin(cfg, s, "dt_s", dt_s, 0.0, true);
    duration_s = hymm::core::readDoubleMin(cfg, s, "duration_s", duration_s, 0.0, false);
    laps = hymm::core::readInt(cfg, s, "laps", laps);
    if (laps < 1) throwConfigError(s, "laps", std::to_string(laps), "must be >= 1");
    start_time_s = hymm::core::readDoubleMin(cfg, s, "start_time_s", start_time_s, 0.0, false);
}

void Scenario::Options::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                         const std::string& s) const
{
    cfg.write(s, "name", name);
    cfg.write(s, "seed", std::to_string(seed));
    detail::writeNumber(cfg, s, "dt_s", dt_s);
    detail::writeNumber(cfg, s, "duration_s", duration_s);
    cfg.write(s, "laps", std::to_string(laps));
    detail::writeNumber(cfg, s, "start_time_s", start_time_s);
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
