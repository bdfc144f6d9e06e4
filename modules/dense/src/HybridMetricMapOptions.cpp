#include "hymm/dense/HybridMetricMap.h"

#include <hymm/core/config_utils.h>

#include <cmath>

namespace hymm::dense
{
hymm::core::OptionTable HybridMetricMap::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.flag("enable_points", enable_points, "keep raw returns (Sec. 3.9); `[DenseSlam] dense_layers` overrides");
    t.flag("enable_occupancy", enable_occupancy, "keep occupancy grids (Sec. 4.1); `[DenseSlam] dense_layers` overrides");
    t.flag("enable_particles", enable_particles, "keep particle sets (Sec. 4.2); `[DenseSlam] dense_layers` overrides");
    t.flag("enable_sog", enable_sog, "keep sums of Gaussians (Sec. 4.3); `[DenseSlam] dense_layers` overrides");
    t.flag("enable_property", enable_property, "keep scalar property grids; `[DenseSlam] dense_layers` overrides");
    t.real("max_range_m", max_range_m, "m", above(0, 1000), "returns beyond are free space only (Table 4.1)");
    t.real("no_return_free_range_m", no_return_free_range_m, "m", atLeast(0, 1000),
           "beams with no return are free space up to min(this, `max_range_m`); 0 = off");
    t.integer("coarsen_every_n_scans", coarsen_every_n_scans, "scans", 0, 1000000,
              "insertScan() runs coarsenIdleRegions() every n scans; 0 = only when called");
    t.real("fallback_max_distance_m", fallback_max_distance_m, "m", atLeast(0, 1e4),
           "a return in no region is kept in the frame of the nearest region whose current triangle is at most "
           "this far (`FallbackTiles.h`); 0 = off");
    t.real("fallback_tile_m", fallback_tile_m, "m", above(0, 1e4), "side of the square fallback tiles (two triangles each)");
    t.flag("enable_profiler", enable_profiler, "CTimeLogger sections `dense.*`");
    return t;
}

void HybridMetricMap::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void HybridMetricMap::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
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
