#include "hymm/dense/HybridMetricMap.h"

#include "hymm/dense/LayerRegistry.h"

#include <hymm/core/config_utils.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace hymm::dense
{
hymm::core::OptionTable HybridMetricMap::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    for (const LayerKind& k : layerKinds())
        t.flag(std::string("enable_") + k.name, this->*(k.enabled),
               std::string(k.doc) + "; `[DenseSlam] dense_layers` overrides");
    t.real("max_range_m", max_range_m, "m", above(0, 1000), "returns beyond are free space only (Table 4.1)");
    t.real("no_return_free_range_m", no_return_free_range_m, "m", atLeast(0, 1000),
           "beams with no return are free space up to min(this, `max_range_m`); 0 = off");
    t.integer("coarsen_every_n_scans", coarsen_every_n_scans, "scans", 0, 1000000,
              "insertScan() runs coarsenIdleRegions() every n scans; 0 = only when called");
    t.real("fallback_max_distance_m", fallback_max_distance_m, "m", atLeast(0, 1e4),
           "a return in no region is kept in the frame of the nearest region whose current triangle is at most "
           "this far (`FallbackTiles.h`); 0 = off");
    t.real("fallback_tile_m", fallback_tile_m, "m", above(0, 1e4), "side of the square fallback tiles (two triangles each)");
    t.real("fallback_reuse_m", fallback_reuse_m, "m", atLeast(0, 1e4),
           "a return goes to an existing fallback tile holding it whose anchor is at most this much farther than "
           "the nearest region (fewer overlapping tiles to update per scan); 0 = always the nearest region's tile");
    t.choice("fallback_frame", fallback_frame, {{"affine", FallbackFrame::Affine}, {"rigid", FallbackFrame::Rigid}},
             "how fallback content follows its anchor region: its affine map extrapolated (Eq. 3.3), or the "
             "rotation and translation fitted to its vertices, which does not extrapolate the triangle's "
             "deformation (`FallbackTiles.h`)");
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
    for (const LayerKind& k : layerKinds()) k.load(*this, cfg);
}

void HybridMetricMap::Options::saveAll(mrpt::config::CConfigFileBase& cfg) const
{
    saveToConfigFile(cfg, "HybridMetricMap");
    for (const LayerKind& k : layerKinds()) k.save(*this, cfg);
}

void HybridMetricMap::Options::validate(const std::string& s) const
{
    if (!(max_range_m > 0))
        hymm::core::throwConfigError(s, "max_range_m", std::to_string(max_range_m), "must be > 0");
    const auto& kinds = layerKinds();
    if (std::none_of(kinds.begin(), kinds.end(), [this](const LayerKind& k) { return this->*(k.enabled); }))
    {
        std::string flags;
        for (const LayerKind& k : kinds) flags += (flags.empty() ? "" : ", ") + std::string("enable_") + k.name;
        hymm::core::throwConfigError(s, std::string("enable_") + kinds.front().name, "false",
                                     "at least one of " + flags + " must be true");
    }
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
    if (!(fallback_reuse_m >= 0) || !std::isfinite(fallback_reuse_m))
        hymm::core::throwConfigError(
            s, "fallback_reuse_m", std::to_string(fallback_reuse_m), "must be finite and >= 0 (0 = nearest region)");
    for (const LayerKind& k : kinds) k.validate(*this);
}

}  // namespace hymm::dense
