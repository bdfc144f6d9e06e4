/**
 * @file ScanOdometryOptions.cpp
 * @brief ScanOdometry's ini keys, counters and construction from a config (ScanOdometry.h).
 */
#include "hymm/scanslam/ScanOdometry.h"

#include <hymm/core/laser_noise.h>
#include <hymm/scanslam/CorrelativeMatcher.h>
#include <hymm/scanslam/matcher_choice.h>

#include <cmath>

namespace hymm::scanslam
{
core::OptionTable ScanOdometry::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.flag("enabled", enabled,
           "fuse the alignment of each scan to the previous one with the wheel odometry in between");
    declareMatcherChoice(t, matcher, "scan matcher of the consecutive scans (its keys in [ScanOdometryMatcher])");
    t.real("max_range_m", max_range_m, "m", above(0, 10000), "returns farther away are not aligned");
    t.integer("max_points", max_points, "", 3, 1000000,
              "the previous scan is thinned evenly to at most this many points");
    t.real("gate_prob", gate_prob, "", between(0, 1),
           "chi-square(3) gate on the aligned minus the wheel increment (0 or 1: none)");
    t.real("cov_scale", cov_scale, "", above(0, 1000),
           "the matcher's covariance of a consecutive pair times this (measured, see above)");
    t.real("min_std_xy_m", min_std_xy_m, "m", atLeast(0, 10), "std added to the aligned increment in x and y");
    t.real("min_std_phi_deg", min_std_phi, "deg", atLeast(0, 180), "std added to its angle", M_PI / 180);
    t.real("std_xy_per_m", std_xy_per_m, "", atLeast(0, 10), "std added in x and y per metre travelled");
    t.real("std_phi_deg_per_m", std_phi_per_m, "deg/m", atLeast(0, 180), "std added to the angle per metre travelled",
           M_PI / 180);
    t.real("keyframe_distance_m", keyframe_distance_m, "m", atLeast(0, 1000),
           "align to a keyframe scan until the vehicle is this far from it (0: to the previous scan)");
    t.real("keyframe_angle_deg", keyframe_angle, "deg", above(0, 180), "or has turned this much", M_PI / 180);
    t.real("step_cov_scale", step_cov_scale, "", above(0, 1000),
           "the covariance of every fused increment handed to the filter times this (steps share scans, see above)");
    t.choice("keyframe_step_cov", keyframe_step_cov,
             {{"alignment", KeyframeStepCov::alignment}, {"growth", KeyframeStepCov::growth}},
             "covariance of a step inside a keyframe: the alignment's, or the growth of the keyframe-relative pose's");
    t.real("heading_cov_scale", heading_cov_scale, "", above(0, 1000),
           "the alignment's heading variance times this, on top of cov_scale");
    t.flag("wheel_turn_bias", wheel_turn_bias,
           "estimate the wheels' turn per metre travelled from the alignments and remove it from the wheel increments");
    t.real("wheel_turn_bias_prior_deg_per_m", wheel_turn_bias_prior, "deg/m", above(0, 180),
           "prior std of the wheels' turn per metre", M_PI / 180);
    t.real("wheel_turn_bias_walk_deg_per_m", wheel_turn_bias_walk, "deg/m/sqrt(m)", atLeast(0, 180),
           "random walk of that turn: std of its change per square root of a metre travelled", M_PI / 180);
    t.real("wheel_turn_bias_min_sigmas", wheel_turn_bias_min_sigmas, "sigma", atLeast(0, 1000),
           "the estimate corrects the wheels only while it is this many of its std from zero");
    return t;
}

void ScanOdometry::Options::load(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    table().load(cfg, section);
    // The return noise is [Laser]'s (the section has no noise keys of its own).
    core::applyLaserNoise(cfg, section, "std_range_m", "std_bearing_deg", noise.std_range_m, noise.std_bearing);
}

std::vector<std::pair<std::string, size_t>> ScanOdometry::Stats::list() const
{
    std::vector<std::pair<std::string, size_t>> out = {
        {"scans", scans}, {"no_reference", no_reference}, {"too_few_points", too_few_points}};
    for (const auto& [reason, n] : align_failed) out.emplace_back("align_failed." + reason, n);
    out.emplace_back("gated", gated);
    out.emplace_back("fused", fused);
    out.emplace_back("keyframes", keyframes);
    out.emplace_back("bias_updates", bias_updates);
    out.emplace_back("bias_gated", bias_gated);
    out.emplace_back("bias_applied", bias_applied);
    out.emplace_back("growth_clamped", growth_clamped);
    return out;
}

ScanOdometry::Options ScanOdometry::loadOptions(const mrpt::config::CConfigFileBase* cfg)
{
    Options o;
    if (cfg)
    {
        o.load(*cfg, "ScanOdometry");
        (void)odometryMatcher(o.matcher, cfg);
    }
    return o;
}

std::unique_ptr<ScanMatcher> ScanOdometry::odometryMatcher(const std::string& kind,
                                                           const mrpt::config::CConfigFileBase* cfg)
{
    if (kind != "correlative") return makeMatcher(kind, cfg, "ScanOdometryMatcher");
    // Consecutive scans: the wheels predict within a few decimetres and degrees, and a
    // whole scan's likelihood grid at the template default (0.03 m) would cost 10x more.
    CorrelativeMatcher::Options o;
    o.grid_resolution_m = 0.1;
    o.search_xy_m = 0.4;
    o.search_phi = 4 * M_PI / 180;
    if (cfg) o.load(*cfg, "ScanOdometryMatcher");
    return std::make_unique<CorrelativeMatcher>(o);
}

std::unique_ptr<ScanOdometry> ScanOdometry::make(const Options& options, const mrpt::config::CConfigFileBase* cfg)
{
    return std::make_unique<ScanOdometry>(options, odometryMatcher(options.matcher, cfg));
}

}  // namespace hymm::scanslam
