#include "hymm/extract/ReflectorExtractor.h"

#include <hymm/core/config_utils.h>
#include <mrpt/math/wrap2pi.h>

#include "scan_beams.h"

#include <cmath>
#include <stdexcept>

namespace hymm::extract
{
namespace
{
constexpr double kDeg = 3.14159265358979323846 / 180.0;
}  // namespace

hymm::core::OptionTable ReflectorExtractor::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.integer("min_intensity", min_intensity, "sensor units", 0, 1000000, "beams at or above mark a reflector");
    t.real("range_jump", range_jump, "m", above(0, 10), "range step that splits two reflectors");
    t.integer("min_points", min_points, "beams", 1, 10000, "smaller clusters are rejected");
    t.real("max_width", max_width, "m", above(0, 100), "wider bright clusters (e.g. a shiny wall) are rejected");
    t.real("beacon_radius", beacon_radius, "m", atLeast(0, 10), "radius of cylindrical beacons (0: flat or point)");
    t.real("min_range", min_range, "m", atLeast(0, 1000), "shorter returns are skipped");
    t.real("max_range", max_range, "m", above(0, 1000), "returns at or beyond this (or the scan's maxRange) are skipped");
    t.real("std_range", std_range, "m", atLeast(0, 10), "range noise put in the observation");
    t.real("std_bearing_deg", std_bearing, "deg", atLeast(0, 90), "bearing noise put in the observation", kDeg);
    return t;
}

void ReflectorExtractor::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void ReflectorExtractor::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void ReflectorExtractor::Options::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    auto num = [](double v) { return std::to_string(v); };
    if (!(range_jump > 0)) throwConfigError(s, "range_jump", num(range_jump), "must be > 0");
    if (min_points < 1) throwConfigError(s, "min_points", std::to_string(min_points), "must be >= 1");
    if (!(max_width > 0)) throwConfigError(s, "max_width", num(max_width), "must be > 0");
    if (!(beacon_radius >= 0))
        throwConfigError(s, "beacon_radius", num(beacon_radius), "must be >= 0");
    if (!(min_range >= 0)) throwConfigError(s, "min_range", num(min_range), "must be >= 0");
    if (!(max_range > min_range))
        throwConfigError(s, "max_range", num(max_range), "must be > min_range");
    if (!(std_range >= 0)) throwConfigError(s, "std_range", num(std_range), "must be >= 0");
    if (!(std_bearing >= 0))
        throwConfigError(s, "std_bearing_deg", num(std_bearing / kDeg), "must be >= 0");
}

ReflectorExtractor::ReflectorExtractor(const Options& options) : options_(options)
{
    options_.validate();
}

ReflectorExtractor::Result ReflectorExtractor::extract(
    const mrpt::obs::CObservation2DRangeScan& scan) const
{
    if (!scan.hasIntensity())
        throw std::invalid_argument(
            "ReflectorExtractor: scan '" + scan.sensorLabel +
            "' has no intensity channel (hasIntensity() is false)");
    const Options& o = options_;
    Result res;
    const auto beams = internal::classifyBeams(scan, o.min_range, o.max_range, res.beams);
    res.skipped_invalid = res.beams.invalid + res.beams.not_finite + res.beams.out_of_range;

    const auto clusters = internal::clusterBeams(
        beams, o.range_jump, [&](size_t i) { return scan.getScanIntensity(i) >= o.min_intensity; });
    res.clusters = clusters.size();

    for (const auto& c : clusters)
    {
        if (c.size() < static_cast<size_t>(o.min_points))
        {
            ++res.rejected_too_few_points;
            continue;
        }
        const auto pts = internal::clusterPoints(beams, c);
        if ((pts.back() - pts.front()).norm() > o.max_width)
        {
            ++res.rejected_too_wide;
            continue;
        }
        Eigen::Vector2d mean = Eigen::Vector2d::Zero();
        for (const auto& p : pts) mean += p;
        mean /= static_cast<double>(pts.size());

        ScanFeature f;
        const double surface_range = mean.norm();
        f.range = surface_range + o.beacon_radius;
        f.bearing = mrpt::math::wrapToPi(std::atan2(mean.y(), mean.x()));
        f.diameter = 2.0 * o.beacon_radius;
        // Spread of the points about the mean: a diagnostic of how point-like the cluster is.
        double ss = 0;
        for (const auto& p : pts) ss += (p - mean).squaredNorm();
        f.fit_rms = std::sqrt(ss / static_cast<double>(pts.size()));
        f.first_beam = c.first;
        f.last_beam = c.last;
        res.reflectors.push_back(f);
    }
    return res;
}

mrpt::obs::CObservationBearingRange ReflectorExtractor::extractObservation(
    const mrpt::obs::CObservation2DRangeScan& scan) const
{
    return toBearingRangeObservation(
        scan, extract(scan).reflectors,
        BearingRangeNoise{options_.std_range, options_.std_bearing});
}

}  // namespace hymm::extract
