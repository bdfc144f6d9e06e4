#include "hymm/extract/TreeExtractor.h"

#include <hymm/core/config_utils.h>
#include <mrpt/math/wrap2pi.h>

#include "hymm/extract/circle_fit.h"
#include "scan_beams.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace hymm::extract
{
namespace
{
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// Keeps the fallback's tangent half-angle below 90 deg (a cluster spanning the whole
// field of view is not a trunk, but must not divide by zero either).
constexpr double kMaxHalfWidth = 0.49 * kPi;

using internal::Beam;
using internal::Cluster;

// True if the raw return of beam `i` is a real echo closer than `range`: something in
// front of the cluster edge hides part of the object.
bool returnsCloser(const mrpt::obs::CObservation2DRangeScan& scan, size_t i, double range)
{
    if (!scan.getScanRangeValidity(i)) return false;
    const double r = scan.getScanRange(i);
    return std::isfinite(r) && r >= 0 && r < range;
}

bool isOccluded(const mrpt::obs::CObservation2DRangeScan& scan, const std::vector<Beam>& beams,
                const Cluster& c)
{
    if (c.first > 0 && returnsCloser(scan, c.first - 1, beams[c.first].range)) return true;
    if (c.last + 1 < beams.size() && returnsCloser(scan, c.last + 1, beams[c.last].range))
        return true;
    return false;
}

struct TrunkModel
{
    Eigen::Vector2d centre;
    double radius = 0;
    bool fallback = false;
};

// Fallback circle: centre on the mean bearing at (closest range + r); the n beams that
// hit the trunk span on average n beam spacings between the two tangent lines, and a
// tangent at half-angle a from the centre direction gives sin(a) = r / (closest + r).
TrunkModel fallbackModel(const std::vector<Beam>& beams, const Cluster& c, double spacing)
{
    double closest = beams[c.first].range, sum_sin = 0, sum_cos = 0;
    for (size_t i = c.first; i <= c.last; ++i)
    {
        closest = std::min(closest, beams[i].range);
        sum_sin += std::sin(beams[i].angle);
        sum_cos += std::cos(beams[i].angle);
    }
    const double bearing = std::atan2(sum_sin, sum_cos);
    const double s = std::sin(std::min(0.5 * spacing * static_cast<double>(c.size()), kMaxHalfWidth));
    TrunkModel m;
    m.radius = closest * s / (1.0 - s);
    m.centre = (closest + m.radius) * Eigen::Vector2d(std::cos(bearing), std::sin(bearing));
    m.fallback = true;
    return m;
}

std::optional<TrunkModel> fittedModel(
    const std::vector<Eigen::Vector2d>& pts, const std::vector<Beam>& beams, const Cluster& c,
    const TrunkModel& width_model, double max_ratio)
{
    const auto circle = fitCircle(pts);
    if (!circle) return std::nullopt;
    double closest = beams[c.first].range;
    for (size_t i = c.first; i <= c.last; ++i) closest = std::min(closest, beams[i].range);
    // A trunk is convex towards the sensor: its centre is farther than its nearest point.
    if (!(circle->centre.norm() > closest)) return std::nullopt;
    const double ratio = circle->radius / std::max(width_model.radius, 1e-9);
    if (ratio > max_ratio || ratio < 1.0 / max_ratio) return std::nullopt;
    return TrunkModel{circle->centre, circle->radius, false};
}

/** The counter of the first acceptance test (fit, smallest and largest diameter) a trunk
 *  fails, nullptr when it passes them all. */
size_t* failedAcceptance(const TreeExtractor::Options& o, const ScanFeature& f, TreeExtractor::Rejections& r)
{
    if (!(f.fit_rms <= o.max_fit_rms)) return &r.bad_fit;
    if (f.diameter < o.min_diameter) return &r.too_small;
    if (f.diameter > o.max_diameter) return &r.too_large;
    return nullptr;
}
}  // namespace

hymm::core::OptionTable TreeExtractor::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("min_diameter", min_diameter, "m", above(0, 10), "smallest accepted trunk diameter");
    t.real("max_diameter", max_diameter, "m", above(0, 10), "largest accepted trunk diameter (> min_diameter)");
    t.real("range_jump", range_jump, "m", above(0, 10), "range step between consecutive beams that splits clusters");
    t.integer("min_points", min_points, "beams", 1, 10000, "clusters with fewer beams are rejected");
    t.integer("fit_min_points", fit_min_points, "beams", 3, 10000,
              "clusters with fewer beams get the angular-width model instead of a circle fit");
    t.real("min_range", min_range, "m", atLeast(0, 1000), "shorter returns are skipped");
    t.real("max_range", max_range, "m", above(0, 1000),
           "returns at or beyond this (or the scan's maxRange) are skipped");
    t.real("max_fit_rms", max_fit_rms, "m", above(0, 10), "largest RMS distance of the points to the fitted circle");
    t.real("max_fit_width_ratio", max_fit_width_ratio, "", above(1, 100),
           "circle fit kept only if fitted / angular-width diameter is within [1/ratio, ratio]");
    t.flag("reject_occluded", reject_occluded, "reject clusters next to a closer return");
    t.flag("reject_scan_edges", reject_scan_edges, "reject clusters touching the first or last beam");
    t.real("std_range", std_range, "m", atLeast(0, 10), "range noise put in the observation");
    t.real("std_bearing_deg", std_bearing, "deg", atLeast(0, 90), "bearing noise put in the observation", kDeg);
    return t;
}

void TreeExtractor::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void TreeExtractor::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void TreeExtractor::Options::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    auto num = [](double v) { return std::to_string(v); };
    if (!(min_diameter > 0)) throwConfigError(s, "min_diameter", num(min_diameter), "must be > 0");
    if (!(max_diameter >= min_diameter))
        throwConfigError(s, "max_diameter", num(max_diameter), "must be >= min_diameter");
    if (!(range_jump > 0)) throwConfigError(s, "range_jump", num(range_jump), "must be > 0");
    if (min_points < 1) throwConfigError(s, "min_points", std::to_string(min_points), "must be >= 1");
    if (fit_min_points < 3)
        throwConfigError(s, "fit_min_points", std::to_string(fit_min_points),
                         "must be >= 3 (a circle has 3 parameters)");
    if (!(min_range >= 0)) throwConfigError(s, "min_range", num(min_range), "must be >= 0");
    if (!(max_range > min_range))
        throwConfigError(s, "max_range", num(max_range), "must be > min_range");
    if (!(max_fit_rms > 0)) throwConfigError(s, "max_fit_rms", num(max_fit_rms), "must be > 0");
    if (!(max_fit_width_ratio > 1))
        throwConfigError(s, "max_fit_width_ratio", num(max_fit_width_ratio), "must be > 1");
    if (!(std_range >= 0)) throwConfigError(s, "std_range", num(std_range), "must be >= 0");
    if (!(std_bearing >= 0))
        throwConfigError(s, "std_bearing_deg", num(std_bearing / kDeg), "must be >= 0");
}

TreeExtractor::TreeExtractor(const Options& options) : options_(options)
{
    options_.validate();
}

TreeExtractor::Result TreeExtractor::extract(const mrpt::obs::CObservation2DRangeScan& scan) const
{
    const Options& o = options_;
    Result res;

    // 1. Beam validation.
    const auto beams = internal::classifyBeams(scan, o.min_range, o.max_range, res.beams);
    res.skipped_invalid = res.beams.invalid + res.beams.not_finite + res.beams.out_of_range;

    // 2. Clustering by range discontinuities.
    const auto clusters = internal::clusterBeams(beams, o.range_jump, [](size_t) { return true; });
    res.clusters = clusters.size();
    const double spacing = internal::beamSpacing(scan);

    for (const auto& c : clusters)
    {
        if (c.size() < static_cast<size_t>(o.min_points))
        {
            ++res.rejected.too_few_points;
            continue;
        }
        // 3. Partial views give wrong diameters.
        if (o.reject_scan_edges && (c.first == 0 || c.last + 1 == beams.size()))
        {
            ++res.rejected.scan_edge;
            continue;
        }
        if (o.reject_occluded && isOccluded(scan, beams, c))
        {
            ++res.rejected.occluded;
            continue;
        }

        // 4. Circle model: least-squares fit, or the angular-width fallback.
        const auto pts = internal::clusterPoints(beams, c);
        const TrunkModel width_model = fallbackModel(beams, c, spacing);
        std::optional<TrunkModel> model;
        if (c.size() >= static_cast<size_t>(o.fit_min_points))
            model = fittedModel(pts, beams, c, width_model, o.max_fit_width_ratio);
        if (!model) model = width_model;

        // 5. Acceptance.
        ScanFeature f;
        f.fit_rms = circleRms(pts, model->centre, model->radius);
        f.diameter = 2.0 * model->radius;
        if (size_t* failed = failedAcceptance(o, f, res.rejected))
        {
            ++*failed;
            continue;
        }
        f.range = model->centre.norm();
        f.bearing = mrpt::math::wrapToPi(std::atan2(model->centre.y(), model->centre.x()));
        f.first_beam = c.first;
        f.last_beam = c.last;
        f.used_fallback = model->fallback;
        res.trees.push_back(f);
    }
    return res;
}

mrpt::obs::CObservationBearingRange TreeExtractor::extractObservation(
    const mrpt::obs::CObservation2DRangeScan& scan) const
{
    return toBearingRangeObservation(
        scan, extract(scan).trees, BearingRangeNoise{options_.std_range, options_.std_bearing});
}

}  // namespace hymm::extract
