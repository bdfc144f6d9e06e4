#include "hymm/dense/ParticlesLayer.h"

#include <hymm/core/config_utils.h>

#include <cmath>
#include <limits>
#include <string>

namespace hymm::dense
{
hymm::core::OptionTable ParticlesLayer::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.integer("samples_per_return", samples_per_return, "", 1, 10000, "samples drawn from the sensor model per return");
    t.real("range_std_m", range_std_m, "m", above(0, 10), "sensor range noise when the scan carries none (Table 4.1); hymm-slam: `[Laser] std_range_m`");
    t.real("bearing_std_deg", bearing_std_deg, "deg", openInterval(0, 60),
           "sensor bearing noise when the scan carries none (Table 4.1); hymm-slam: `[Laser] std_bearing_deg`");
    t.real("prob_min", prob_min, "", openInterval(0, 0.5), "p_min of Eq. 4.4: occupancy deep in free space");
    t.real("prob_max", prob_max, "", openInterval(0.5, 1), "p_max of Eq. 4.4: occupancy at the return");
    t.real("d_min_m", d_min_m, "m", above(0, 100), "association distance, Eq. 4.10 (Sec. 4.2.3)");
    t.flag("position_averaging", position_averaging, "move associated particles to the mean (Sec. 4.2.3)");
    t.flag("free_space_update", free_space_update, "step 4: vacated areas lose weight");
    t.flag("free_space_protection", free_space_protection,
           "the free-space step leaves particles explained by a return of the scan (`d_min`) or hidden behind one of "
           "their own beams' returns");
    t.real("min_weight", min_weight, "", halfOpen(0, 0.5), "particles below are removed");
    t.real("max_weight", max_weight, "", halfOpen(0.5, 1), "upper clamp so particles stay revisable (>= prob_max)");
    t.integer("max_particles", max_particles, "", 0, 100000000, "per region; 0 = unbounded (thesis: no subsampling)");
    t.integer("max_per_cell", max_per_cell, "", 0, 100000000,
              "particles kept per square cell of side `d_min_m`, the heaviest; bounds a region revisited many times "
              "(0 = unbounded, thesis)");
    t.integer("random_seed", random_seed, "", std::numeric_limits<int>::min(), std::numeric_limits<int>::max(),
              "mixed with the region's vertices: reproducible maps");
    t.real("render_min_weight", render_min_weight, "", between(0, 1), "renderInto draws particles with w >= this");
    return t;
}

void ParticlesLayer::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void ParticlesLayer::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void ParticlesLayer::Options::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    const auto str = [](double v) { return std::to_string(v); };
    if (samples_per_return < 1)
        throwConfigError(s, "samples_per_return", str(samples_per_return), "must be >= 1");
    if (!(range_std_m > 0) || !std::isfinite(range_std_m))
        throwConfigError(s, "range_std_m", str(range_std_m), "must be finite and > 0");
    if (!(bearing_std_deg > 0 && bearing_std_deg < 60))
        throwConfigError(s, "bearing_std_deg", str(bearing_std_deg), "must be in (0, 60)");
    if (!(prob_min > 0 && prob_min < 0.5))
        throwConfigError(s, "prob_min", str(prob_min), "must be in (0, 0.5)");
    if (!(prob_max > 0.5 && prob_max < 1))
        throwConfigError(s, "prob_max", str(prob_max), "must be in (0.5, 1)");
    if (!(d_min_m > 0) || !std::isfinite(d_min_m))
        throwConfigError(s, "d_min_m", str(d_min_m), "must be finite and > 0");
    if (!(min_weight >= 0 && min_weight < 0.5))
        throwConfigError(s, "min_weight", str(min_weight), "must be in [0, 0.5)");
    if (!(max_weight >= prob_max && max_weight < 1))
        throwConfigError(s, "max_weight", str(max_weight), "must be in [prob_max, 1)");
    if (max_particles < 0) throwConfigError(s, "max_particles", str(max_particles), "must be >= 0");
    if (max_per_cell < 0) throwConfigError(s, "max_per_cell", str(max_per_cell), "must be >= 0");
    if (!(render_min_weight >= 0 && render_min_weight <= 1))
        throwConfigError(s, "render_min_weight", str(render_min_weight), "must be in [0, 1]");
}

RangeBearingNoise ParticlesLayer::Options::noise() const
{
    return {range_std_m, bearing_std_deg * M_PI / 180.0};
}

}  // namespace hymm::dense
