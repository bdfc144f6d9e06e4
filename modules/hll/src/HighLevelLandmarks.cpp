/**
 * @file HighLevelLandmarks.cpp
 * @brief High-level landmarks (thesis 6.1): periodic search, pending templates,
 *        initialisation from the next observation, observation by scan alignment.
 */
#include "hymm/hll/HighLevelLandmarks.h"

#include <hymm/core/laser_noise.h>
#include <hymm/scanslam/matcher_choice.h>

#include <hymm/ekf/pose_landmark_model.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hymm::hll
{
core::OptionTable HighLevelLandmarks::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.flag("enabled", enabled, "search the dense maps for high-level landmarks (thesis 6.1)");
    t.include(detector.table());
    scanslam::declareMatcherChoice(t, matcher, "scan matcher that observes the HLL templates (its keys in [HllMatcher])");
    t.real("in_view_fraction", in_view_fraction, "", between(0, 1),
           "share of a template's points in the sensor's view to attempt an alignment");
    t.real("gate_prob", gate_prob, "", between(0, 1), "NN gate on an aligned observation");
    t.integer("template_max_points", template_max_points, "", 3, 100000000,
              "an HLL template keeps at most this many Gaussians (even stride)");
    t.real("std_range_m", std_range_m, "m", above(0, 10),
           "range noise of the scan points aligned to; deprecated: [Laser] std_range_m");
    t.real("std_bearing_deg", std_bearing, "deg", above(0, 60),
           "bearing noise of the scan points; deprecated: [Laser] std_bearing_deg",
           M_PI / 180);
    t.real("visible_bin_deg", visible_bin, "deg", above(0),
           "only the template points visible from the prediction are aligned: bearing bins of this size",
           M_PI / 180);
    t.real("visible_depth_tol_m", visible_depth_tol_m, "m", atLeast(0),
           "a template point this close behind the nearest of its bearing bin is visible");
    t.real("explain_distance_m", explain_distance_m, "m", atLeast(0),
           "a return this close to an aligned HLL template is that HLL's");
    return t;
}

std::vector<std::pair<std::string, size_t>> HighLevelLandmarks::Stats::list() const
{
    return {{"searches", searches},
            {"regions_searched", regions_searched},
            {"components_dropped", components_dropped},
            {"corners_near_landmark", corners_near_landmark},
            {"corners", corners},
            {"proposed", proposed},
            {"accepted", accepted},
            {"rejected_few_gaussians", rejected_few_gaussians},
            {"rejected_short_outline", rejected_short_outline},
            {"rejected_overlap_landmark", rejected_overlap_landmark},
            {"rejected_overlap_candidate", rejected_overlap_candidate},
            {"init_attempts", init_attempts},
            {"init_align_failed", init_align_failed},
            {"initialised", initialised},
            {"lost", lost}};
}

HighLevelLandmarks::Options HighLevelLandmarks::loadOptions(const mrpt::config::CConfigFileBase* cfg)
{
    Options o;
    if (cfg)
    {
        o.table().load(*cfg, "HighLevelLandmarks");
        core::applyLaserNoise(*cfg, "HighLevelLandmarks", "std_range_m", "std_bearing_deg", o.std_range_m,
                              o.std_bearing);
        // The matcher's section is checked (and so known to a strict file) even when
        // the HLLs are off: the same file runs with and without them.
        (void)scanslam::makeMatcher(o.matcher, cfg, "HllMatcher");
    }
    return o;
}

std::unique_ptr<HighLevelLandmarks> HighLevelLandmarks::fromConfig(const mrpt::config::CConfigFileBase* cfg)
{
    return make(loadOptions(cfg), cfg);
}

std::unique_ptr<HighLevelLandmarks> HighLevelLandmarks::make(const Options& o,
                                                             const mrpt::config::CConfigFileBase* cfg)
{
    return std::make_unique<HighLevelLandmarks>(o, scanslam::makeMatcher(o.matcher, cfg, "HllMatcher"));
}

HighLevelLandmarks::HighLevelLandmarks(const Options& options, std::unique_ptr<scanslam::ScanMatcher> matcher)
    : options_(options), detector_(options.detector)
{
    if (!matcher) throw std::invalid_argument("HighLevelLandmarks: no matcher");
    scanslam::ScanLandmarkMap::Options t;
    t.matcher = matcher->name();
    t.noise.std_range_m = options_.std_range_m;
    t.noise.std_bearing = options_.std_bearing;
    t.in_view_fraction = options_.in_view_fraction;
    t.gate_prob = options_.gate_prob;
    t.explain_distance_m = options_.explain_distance_m;
    t.visible_bin = options_.visible_bin;
    t.visible_depth_tol_m = options_.visible_depth_tol_m;
    t.create_landmarks = false;  // only HLL templates; no segment becomes a landmark here
    tracker_ = std::make_unique<scanslam::ScanLandmarkMap>(t, scanslam::Segmenter::Options{},
                                                           scanslam::SegmentAcceptance::Options{},
                                                           std::move(matcher));
}

bool HighLevelLandmarks::due(double t)
{
    if (!std::isfinite(t)) return false;
    if (std::isnan(last_search_t_)) last_search_t_ = t;  // the clock starts with the log
    return t - last_search_t_ >= options_.detector.period_s;
}

scanslam::ScanTemplate HighLevelLandmarks::makeTemplate(const OrientedRect& rect,
                                                        const std::vector<HllDetector::Gaussian>& gaussians,
                                                        size_t max_points)
{
    std::vector<size_t> inside;
    for (size_t i = 0; i < gaussians.size(); ++i)
        if (rect.contains(gaussians[i].mean)) inside.push_back(i);
    if (inside.empty()) throw std::invalid_argument("makeTemplate: no Gaussian inside the rectangle");
    const size_t n = std::min(inside.size(), std::max<size_t>(max_points, 1));
    scanslam::ScanTemplate tpl;
    // The rectangle's frame (thesis 6.1.2): p_local = R(-phi)(p - c), P_local = R^T P R.
    const scanslam::Mat2 r = scanslam::rotation(rect.phi);
    for (size_t k = 0; k < n; ++k)
    {
        // Even stride over all of them, so a thinned template still spans the whole area.
        const auto& g = gaussians[inside[k * inside.size() / n]];
        tpl.sog.add(rect.toLocal(g.mean), r.transpose() * g.cov * r);
    }
    return tpl;
}

std::vector<OrientedRect> HighLevelLandmarks::areas(const ekf::EkfSlam& ekf) const
{
    std::vector<OrientedRect> out;
    for (const auto& h : hlls_)
    {
        if (h.landmark_id >= 0 && ekf.hasLandmark(h.landmark_id))
        {
            OrientedRect local;
            local.half = h.rect.half;
            out.push_back(local.placed(ekf.landmarkBlockMean(h.landmark_id).head<3>()));
        }
        else
            out.push_back(h.rect);
    }
    return out;
}

const HllDetector::Search& HighLevelLandmarks::search(double t, const ekf::EkfSlam& ekf,
                                                      const ltr::RegionPartition& partition,
                                                      const dense::HybridMetricMap& map,
                                                      const std::vector<OrientedRect>& exclusions)
{
    last_search_t_ = t;
    std::vector<OrientedRect> ex = areas(ekf);
    ex.insert(ex.end(), exclusions.begin(), exclusions.end());
    // The point landmarks (2-DOF blocks): a corner on one of them would duplicate it.
    std::vector<Vec2> points;
    for (long id : ekf.landmarkIds())
        if (ekf.landmarkBlock(id).dim == 2) points.push_back(ekf.landmarkMean(id));
    HllDetector::Search s = detector_.search(ekf.vehiclePose().head<2>(), partition, map, ex, t, points);
    ++stats_.searches;
    stats_.regions_searched += s.regions;
    stats_.components_dropped += s.components_dropped;
    stats_.corners_near_landmark += s.corners_near_landmark;
    stats_.corners += s.corners.size();
    stats_.proposed += s.candidates.size();
    for (const auto& c : s.candidates)
    {
        switch (c.outcome)
        {
            case HllDetector::Outcome::accepted: break;
            case HllDetector::Outcome::too_few_gaussians: ++stats_.rejected_few_gaussians; continue;
            case HllDetector::Outcome::outline_too_short: ++stats_.rejected_short_outline; continue;
            case HllDetector::Outcome::overlaps_landmark: ++stats_.rejected_overlap_landmark; continue;
            case HllDetector::Outcome::overlaps_candidate: ++stats_.rejected_overlap_candidate; continue;
        }
        addPending(c.rect, makeTemplate(c.rect, s.gaussians, options_.template_max_points), c.gaussians, t,
                   c.outline_m);
    }
    s.gaussians.clear();  // the record keeps what the figure draws
    s.gaussians.shrink_to_fit();
    searches_.push_back(std::move(s));
    return searches_.back();
}

size_t HighLevelLandmarks::addPending(const OrientedRect& rect, scanslam::ScanTemplate tpl, size_t gaussians,
                                      double t, double outline_m)
{
    if (tpl.sog.size() < 3) throw std::invalid_argument("HighLevelLandmarks: a template needs 3 points");
    Hll h;
    h.index = hlls_.size();
    h.rect = rect;
    h.gaussians = gaussians;
    h.outline_m = outline_m;
    h.tpl = std::move(tpl);
    h.t_accepted = t;
    hlls_.push_back(std::move(h));
    ++stats_.accepted;
    return hlls_.back().index;
}

void HighLevelLandmarks::processScan(ekf::EkfSlam& ekf, const mrpt::obs::CObservation2DRangeScan& scan,
                                     double t)
{
    for (auto& h : hlls_)
        if (h.landmark_id >= 0 && !ekf.hasLandmark(h.landmark_id) && h.t_initialised >= 0)
        {
            ++stats_.lost;
            h.t_initialised = -2;  // counted once; the area stays excluded at detection
        }
    // Step 3 first: the HLLs in the filter, by alignment (Scan-SLAM's observation step).
    tracker_->processScan(ekf, scan);
    // Step 2: pending HLLs in view are initialised from this scan.
    bool any_pending = false;
    for (const auto& h : hlls_) any_pending |= h.landmark_id < 0;
    if (!any_pending) return;
    const scanslam::PointSet pts = scanslam::fromScan(scan, tracker_->options().noise);
    if (pts.size() < 3) return;
    const auto& sp = scan.sensorPose;
    const scanslam::Vec3 sensor(sp.x(), sp.y(), sp.yaw());
    const double max_range = static_cast<double>(scan.maxRange);
    const double fov = static_cast<double>(scan.aperture);
    for (auto& h : hlls_)
    {
        if (h.landmark_id >= 0) continue;
        // Where the map puts the HLL's frame, seen from the sensor (Eq. 5.15).
        const scanslam::Vec3 z_hat = ekf::poseLandmarkObservation(ekf.vehiclePose(), h.rect.pose(), sensor);
        if (scanslam::fractionInView(h.tpl, z_hat, max_range, fov) <= options_.in_view_fraction) continue;
        ++stats_.init_attempts;
        // Only what the sensor can see of it: the template holds every side the dense map saw.
        const scanslam::AlignResult res = tracker_->matcher().align(
            scanslam::visiblePart(h.tpl.sog, z_hat, max_range, fov, options_.visible_bin,
                                  options_.visible_depth_tol_m),
            pts, z_hat);
        if (!res.ok)
        {
            ++stats_.init_align_failed;
            continue;
        }
        h.landmark_id = tracker_->addTemplateLandmark(ekf, h.tpl, res, sensor);
        h.t_initialised = t;
        ++stats_.initialised;
    }
}

}  // namespace hymm::hll
