#include "hymm/dense/HybridMetricMap.h"

#include <hymm/core/config_utils.h>

namespace hymm::dense
{
void HybridMetricMap::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    using namespace hymm::core;
    checkKnownKeys(cfg, s, {"enable_points", "enable_occupancy", "max_range_m", "enable_profiler"});
    enable_points = readBool(cfg, s, "enable_points", enable_points);
    enable_occupancy = readBool(cfg, s, "enable_occupancy", enable_occupancy);
    max_range_m = readDoubleMin(cfg, s, "max_range_m", max_range_m, 0.0, true);
    enable_profiler = readBool(cfg, s, "enable_profiler", enable_profiler);
    validate(s);
}

void HybridMetricMap::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    cfg.write(s, "enable_points", enable_points);
    cfg.write(s, "enable_occupancy", enable_occupancy);
    cfg.write(s, "max_range_m", max_range_m);
    cfg.write(s, "enable_profiler", enable_profiler);
}

void HybridMetricMap::Options::loadAll(const mrpt::config::CConfigFileBase& cfg)
{
    loadFromConfigFile(cfg, "HybridMetricMap");
    occupancy.loadFromConfigFile(cfg, "OccupancyLayer");
    points.loadFromConfigFile(cfg, "PointsLayer");
}

void HybridMetricMap::Options::saveAll(mrpt::config::CConfigFileBase& cfg) const
{
    saveToConfigFile(cfg, "HybridMetricMap");
    occupancy.saveToConfigFile(cfg, "OccupancyLayer");
    points.saveToConfigFile(cfg, "PointsLayer");
}

void HybridMetricMap::Options::validate(const std::string& s) const
{
    if (!(max_range_m > 0))
        hymm::core::throwConfigError(s, "max_range_m", std::to_string(max_range_m), "must be > 0");
    if (!enable_points && !enable_occupancy)
        hymm::core::throwConfigError(
            s, "enable_points", "false", "at least one of enable_points, enable_occupancy must be true");
    occupancy.validate();
    points.validate();
}

}  // namespace hymm::dense
