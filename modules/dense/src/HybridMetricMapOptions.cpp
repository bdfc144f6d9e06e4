#include "hymm/dense/HybridMetricMap.h"

#include <hymm/core/config_utils.h>

#include <cmath>

namespace hymm::dense
{
void HybridMetricMap::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    using namespace hymm::core;
    checkKnownKeys(
        cfg, s,
        {"enable_points", "enable_occupancy", "enable_particles", "enable_sog", "enable_property", "max_range_m",
         "no_return_free_range_m", "coarsen_every_n_scans", "fallback_max_distance_m", "fallback_tile_m",
         "enable_profiler"});
    enable_points = readBool(cfg, s, "enable_points", enable_points);
    enable_occupancy = readBool(cfg, s, "enable_occupancy", enable_occupancy);
    enable_particles = readBool(cfg, s, "enable_particles", enable_particles);
    enable_sog = readBool(cfg, s, "enable_sog", enable_sog);
    enable_property = readBool(cfg, s, "enable_property", enable_property);
    max_range_m = readDoubleMin(cfg, s, "max_range_m", max_range_m, 0.0, true);
    no_return_free_range_m = readDoubleMin(cfg, s, "no_return_free_range_m", no_return_free_range_m, 0.0, false);
    coarsen_every_n_scans = static_cast<int>(readInt(cfg, s, "coarsen_every_n_scans", coarsen_every_n_scans));
    fallback_max_distance_m =
        readDoubleMin(cfg, s, "fallback_max_distance_m", fallback_max_distance_m, 0.0, false);
    fallback_tile_m = readDoubleMin(cfg, s, "fallback_tile_m", fallback_tile_m, 0.0, true);
    enable_profiler = readBool(cfg, s, "enable_profiler", enable_profiler);
    validate(s);
}

void HybridMetricMap::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    cfg.write(s, "enable_points", enable_points);
    cfg.write(s, "enable_occupancy", enable_occupancy);
    cfg.write(s, "enable_particles", enable_particles);
    cfg.write(s, "enable_sog", enable_sog);
    cfg.write(s, "enable_property", enable_property);
    cfg.write(s, "max_range_m", max_range_m);
    cfg.write(s, "no_return_free_range_m", no_return_free_range_m);
    cfg.write(s, "coarsen_every_n_scans", coarsen_every_n_scans);
    cfg.write(s, "fallback_max_distance_m", fallback_max_distance_m);
    cfg.write(s, "fallback_tile_m", fallback_tile_m);
    cfg.write(s, "enable_profiler", enable_profiler);
}

void HybridMetricMap::Options::loadAll(const mrpt::config::CConfigFileBase& cfg)
{
    loadFromConfigFile(cfg, "HybridMetricMap");
    occupancy.loadFromConfigFile(cfg, "OccupancyLayer");
    points.loadFromConfigFile(cfg, "PointsLayer");
    particles.loadFromConfigFile(cfg, "ParticlesLayer");
    sog.loadFromConfigFile(cfg, "SogLayer");
    property.loadFromConfigFile(cfg, "PropertyLayer");
}

void HybridMetricMap::Options::saveAll(mrpt::config::CConfigFileBase& cfg) const
{
    saveToConfigFile(cfg, "HybridMetricMap");
    occupancy.saveToConfigFile(cfg, "OccupancyLayer");
    points.saveToConfigFile(cfg, "PointsLayer");
    particles.saveToConfigFile(cfg, "ParticlesLayer");
    sog.saveToConfigFile(cfg, "SogLayer");
    property.saveToConfigFile(cfg, "PropertyLayer");
}

void HybridMetricMap::Options::validate(const std::string& s) const
{
    if (!(max_range_m > 0))
        hymm::core::throwConfigError(s, "max_range_m", std::to_string(max_range_m), "must be > 0");
    if (!enable_points && !enable_occupancy && !enable_particles && !enable_sog && !enable_property)
        hymm::core::throwConfigError(
            s, "enable_points", "false",
            "at least one of enable_points, enable_occupancy, enable_particles, enable_sog, enable_property "
            "must be true");
    if (!(no_return_free_range_m >= 0) || !std::isfinite(no_return_free_range_m))
        hymm::core::throwConfigError(
            s, "no_return_free_range_m", std::to_string(no_return_free_range_m),
            "must be finite and >= 0 (0 = beams with no return give no free space)");
    if (coarsen_every_n_scans < 0)
        hymm::core::throwConfigError(
            s, "coarsen_every_n_scans", std::to_string(coarsen_every_n_scans), "must be >= 0 (0 = off)");
    if (!(fallback_max_distance_m >= 0) || !std::isfinite(fallback_max_distance_m))
        hymm::core::throwConfigError(
            s, "fallback_max_distance_m", std::to_string(fallback_max_distance_m), "must be finite and >= 0 (0 = off)");
    if (!(fallback_tile_m > 0) || !std::isfinite(fallback_tile_m))
        hymm::core::throwConfigError(s, "fallback_tile_m", std::to_string(fallback_tile_m), "must be finite and > 0");
    occupancy.validate();
    points.validate();
    particles.validate();
    sog.validate();
    property.validate();
}

}  // namespace hymm::dense
