/**
 * @file ScanLandmarkMap.cpp
 * @brief Scan-SLAM per scan (thesis 5.2, 5.5, 5.7): observation of the templates in view
 *        by alignment, NN gate and EKF update of their pose; new pose landmarks from the
 *        segments of the unexplained returns that pass the acceptance test.
 */
#include <limits>

#include <hymm/core/OptionTable.h>
#include "hymm/scanslam/ScanLandmarkMap.h"

#include <hymm/core/config_utils.h>
#include <hymm/core/laser_noise.h>
#include <hymm/ekf/pose_landmark_model.h>
#include <hymm/scanslam/matcher_choice.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hymm::scanslam
{
/** The wide-search keys of [ScanLandmarks] (ScanLandmarkWide.cpp). */
void declareWideKeys(core::OptionTable& t, ScanLandmarkMap::Options& o);
/** The view_corr_* keys of [ScanLandmarks] (ScanLandmarkAlign.cpp). */
void declareViewCorrKeys(core::OptionTable& t, ScanLandmarkMap::Options& o);

core::OptionTable ScanLandmarkMap::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    declareMatcherChoice(t, matcher, "scan matcher that observes the templates");
    t.real("std_range_m", noise.std_range_m, "m", above(0, 10), "range noise of a return (templates); deprecated: [Laser] std_range_m");
    t.real("std_bearing_deg", noise.std_bearing, "deg", above(0, 60), "bearing noise of a return; deprecated: [Laser] std_bearing_deg",
           M_PI / 180);
    t.real("in_view_fraction", in_view_fraction, "", between(0, 1),
           "share of a template's points in the sensor's view to attempt an alignment (5.3)");
    t.real("gate_prob", gate_prob, "", between(0, 1), "NN gate on the aligned observation, chi-square(3) probability (5.5; 0 or 1: none)");
    t.integer("update_iterations", update_iterations, "", 1, 100,
              "iterated EKF: relinearisations of a local alignment's update at most (1 = the EKF)");
    t.integer("wide_update_iterations", wide_update_iterations, "", 1, 100,
              "the same for a wide-search (loop-closing) update");
    t.flag("merge_duplicates", merge_duplicates,
           "a landmark aligned in a scan and another whose template overlaps it at the estimates become one (relative pose fused, the newer removed)");
    t.real("merge_min_overlap", merge_min_overlap, "", between(0, 1),
           "merge_duplicates: share of the smaller template's points near the other's");
    t.integer("merge_retry_scans", merge_retry_scans, "", 1, 1000000,
              "merge_duplicates: scans before a pair that failed is tried again");
    t.real("explain_distance_m", explain_distance_m, "m", atLeast(0, 100),
           "a return this close to an aligned template is explained");
    t.real("max_creation_range_m", max_creation_range_m, "m", above(0, 10000),
           "segments farther away create no landmark");
    t.real("min_spread_ratio", min_spread_ratio, "", between(0, 1),
           "collinearity test: minor/major spread of a segment");
    t.flag("create_landmarks", create_landmarks,
           "segments of unexplained returns become new landmarks (false: observe only)");
    t.real("visible_bin_deg", visible_bin, "deg", atLeast(0, 180),
           "align only the template points visible from the prediction, bearing bins of this size (0: all)",
           M_PI / 180);
    t.real("visible_depth_tol_m", visible_depth_tol_m, "m", atLeast(0, 100),
           "a template point this close behind the nearest of its bearing bin is visible");
    t.real("view_std_xy_m", view_std_xy_m, "m", atLeast(0, 100),
           "alignment std added in x and y at any viewpoint (measured, see above)");
    t.real("view_std_xy_per_m", view_std_xy_per_m, "", atLeast(0, 10),
           "its growth per metre the template frame moved in the sensor frame since it was made");
    t.real("view_std_phi_deg", view_std_phi, "deg", atLeast(0, 180), "same for the angle", M_PI / 180);
    t.real("view_std_phi_deg_per_m", view_std_phi_per_m, "deg/m", atLeast(0, 180),
           "growth of the angle's std per metre of viewpoint change", M_PI / 180);
    declareViewCorrKeys(t, *this);
    t.real("max_view_change_m", max_view_change_m, "m", atLeast(0, 10000),
           "> 0: templates whose frame moved more than this in the sensor frame are not aligned");
    t.real("max_prediction_std_m", max_prediction_std_m, "m", atLeast(0, 10000),
           "> 0: templates whose predicted position has a larger std are not aligned");
    declareWideKeys(t, *this);
    t.real("augment_above_std_m", augment_above_std_m, "m", atLeast(0, 10000),
           "> 0: templates whose predicted position has a larger std are aligned with the dense map around them added (6.2)");
    t.real("augment_margin_m", augment_margin_m, "m", atLeast(0, 1000),
           "the dense map this far around a template's bounds is added");
    t.integer("augment_max_points", augment_max_points, "", 1, 100000, "dense Gaussians added at most (evenly thinned)");
    t.real("revisit_gap_s", revisit_gap_s, "s", atLeast(0, 1e9),
           "an update of a landmark not updated for this long counts as a revisit (a loop closure through it)");
    t.integer("seed", seed, "", 0, std::numeric_limits<uint32_t>::max(), "acceptance test's random seed");
    return t;
}

void ScanLandmarkMap::Options::load(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    table().load(cfg, section);
    // The state model leaves (1 - c) R to each update: c = 1 would leave nothing.
    if (view_corr_model == ViewCorrModel::State && view_corr_share >= 1)
        throw std::invalid_argument("[" + section + "] view_corr_share must be below 1 with view_corr_model = state");
}

void ScanLandmarkMap::Options::save(mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    auto copy = *this;
    copy.table().save(cfg, section);
}

std::vector<std::pair<std::string, size_t>> ScanLandmarkMap::Stats::list() const
{
    std::vector<std::pair<std::string, size_t>> out = {
        {"scans", scans},
        {"scans_empty", scans_empty},
        {"beams_invalid", beams_invalid},
        {"predicted", predicted},
        {"out_of_view", out_of_view},
        {"view_changed", view_changed},
        {"prediction_uncertain", prediction_uncertain},
        {"aligned", aligned}};
    for (const auto& [reason, n] : align_failed) out.emplace_back("align_failed." + reason, n);
    const std::pair<std::string, size_t> rest[] = {
        {"updated", updated},
        {"gated", gated},
        {"update_numeric", update_numeric},
        {"update_invalid", update_invalid},
        {"returns_explained", returns_explained},
        {"segments", segments},
        {"short_runs", short_runs},
        {"segments_far", segments_far},
        {"segments_collinear", segments_collinear}};
    out.insert(out.end(), std::begin(rest), std::end(rest));
    for (size_t k = 0; k < SegmentAcceptance::kOutcomes; ++k)
        out.emplace_back(std::string("acceptance.") +
                             SegmentAcceptance::outcomeName(static_cast<SegmentAcceptance::Outcome>(k)),
                         acceptance[k]);
    out.emplace_back("creation_failed", creation_failed);
    out.emplace_back("created", created);
    for (const auto& [reason, n] : wide) out.emplace_back("wide." + reason, n);
    out.emplace_back("augmented", augmented);
    out.emplace_back("augment_points", augment_points);
    out.emplace_back("augment_empty", augment_empty);
    out.emplace_back("merge_candidates", merge_candidates);
    out.emplace_back("merge_align_failed", merge_align_failed);
    out.emplace_back("merge_gated", merge_gated);
    out.emplace_back("merged", merged);
    return out;
}

std::unique_ptr<ScanLandmarkMap> ScanLandmarkMap::fromConfig(const mrpt::config::CConfigFileBase* cfg)
{
    Options o;
    Segmenter::Options seg;
    SegmentAcceptance::Options acc;
    if (cfg)
    {
        o.load(*cfg, "ScanLandmarks");
        core::applyLaserNoise(*cfg, "ScanLandmarks", "std_range_m", "std_bearing_deg", o.noise.std_range_m,
                              o.noise.std_bearing);
        seg.load(*cfg, "ScanSegmentation");
        acc.load(*cfg, "ScanAcceptance");
    }
    const std::string section = o.matcher == "sog"   ? "SogMatcher"
                                : o.matcher == "icp" ? "IcpMatcher"
                                                     : "CorrelativeMatcher";
    return std::make_unique<ScanLandmarkMap>(o, seg, acc, makeMatcher(o.matcher, cfg, section));
}

ScanLandmarkMap::ScanLandmarkMap(const Options& options, const Segmenter::Options& segmentation,
                                 const SegmentAcceptance::Options& acceptance,
                                 std::unique_ptr<ScanMatcher> matcher)
    : options_(options),
      segmenter_(segmentation),
      matcher_(std::move(matcher)),
      acceptance_(acceptance, *matcher_, options.seed)
{
}

bool hasOrientation(const PointSet& set, double min_ratio)
{
    if (set.size() < 3) return false;
    Vec2 c = Vec2::Zero();
    for (const Vec2& p : set.points) c += p;
    c /= static_cast<double>(set.size());
    Mat2 s = Mat2::Zero();
    for (const Vec2& p : set.points) s += (p - c) * (p - c).transpose();
    const Eigen::SelfAdjointEigenSolver<Mat2> es(s);
    const Vec2 ev = es.eigenvalues().cwiseMax(0.0);
    return ev[1] > 0 && std::sqrt(ev[0] / ev[1]) >= min_ratio;
}

namespace
{
/** Marks the returns within `d` of a template point placed at z (sensor frame). */
size_t markExplained(const ScanTemplate& tpl, const Vec3& z, const PointSet& pts, double d,
                     std::vector<char>& explained)
{
    const std::vector<Vec2> placed = transformedPoints(tpl.sog.points, z);
    const Vec2 origin = z.head<2>();
    const double reach = templateRadius(tpl) + d, d2 = d * d;
    size_t n = 0;
    for (size_t i = 0; i < pts.size(); ++i)
    {
        if (explained[i] || (pts.points[i] - origin).norm() > reach) continue;
        for (const Vec2& q : placed)
            if ((pts.points[i] - q).squaredNorm() <= d2)
            {
                explained[i] = 1;
                ++n;
                break;
            }
    }
    return n;
}
}  // namespace

void ScanLandmarkMap::processScan(ekf::EkfSlam& ekf, const mrpt::obs::CObservation2DRangeScan& scan)
{
    ++stats_.scans;
    revisits_.setScanTime(scan.timestamp);
    last_aligned_.clear();
    wide_this_scan_ = 0;
    ScanReadStats rs;
    const PointSet pts = fromScan(scan, options_.noise, &rs);
    stats_.beams_invalid += rs.invalid + rs.non_finite + rs.out_of_range;
    // Landmarks the filter dropped (merged, or removed by its owner) take their templates
    // and their wide-search and merge bookkeeping with them (ids are never reused).
    for (auto it = templates_.begin(); it != templates_.end();)
        it = ekf.hasLandmark(it->first) ? std::next(it) : templates_.erase(it);
    const auto prune = [this](auto& by_id) {
        for (auto it = by_id.begin(); it != by_id.end();)
            it = templates_.count(it->first) ? std::next(it) : by_id.erase(it);
    };
    prune(wide_last_);
    prune(fused_views_);
    prune(first_scans_);
    revisits_.prune([this](long id) { return templates_.count(id) > 0; });
    for (auto it = merge_last_.begin(); it != merge_last_.end();)
        it = templates_.count(it->first.first) && templates_.count(it->first.second) ? std::next(it)
                                                                                     : merge_last_.erase(it);
    if (pts.size() < 3)
    {
        ++stats_.scans_empty;
        return;
    }
    const auto& sp = scan.sensorPose;
    const Vec3 sensor(sp.x(), sp.y(), sp.yaw());
    dropApparentBlocks(ekf, sensor);
    const double max_range = static_cast<double>(scan.maxRange);
    const double fov = static_cast<double>(scan.aperture);
    std::vector<char> explained(pts.size(), 0);
    for (const auto& [id, tpl] : templates_) observe(ekf, id, tpl, pts, sensor, max_range, fov, explained);
    if (options_.merge_duplicates) mergeDuplicates(ekf);
    if (options_.create_landmarks) createLandmarks(ekf, pts, sensor, explained);
}

long ScanLandmarkMap::addTemplateLandmark(ekf::EkfSlam& ekf, ScanTemplate tpl, const AlignResult& obs,
                                          const Vec3& sensor, std::vector<Vec2> first_scan)
{
    if (tpl.sog.empty()) throw std::invalid_argument("addTemplateLandmark: empty template");
    if (!obs.ok || !obs.z.allFinite() || !isCovariance(obs.R))
        throw std::invalid_argument("addTemplateLandmark: the observation is not a valid alignment");
    const long id = ekf.addPoseLandmark(obs.z, obs.R, sensor);
    revisits_.created(id);
    tpl.frame_in_sensor = obs.z;
    templates_.emplace(id, std::move(tpl));
    if (keepsFirstScans() && !first_scan.empty()) first_scans_[id] = std::move(first_scan);
    ++stats_.created;
    return id;
}

void ScanLandmarkMap::observe(ekf::EkfSlam& ekf, long id, const ScanTemplate& tpl,
                              const PointSet& pts, const Vec3& sensor, double max_range,
                              double fov, std::vector<char>& explained)
{
    // Predicted pose of the template frame in the sensor frame (Eq. 5.15) at the latest
    // estimate: earlier updates of this scan are already in it.
    const Vec3 z_hat = ekf::poseLandmarkObservation(ekf.vehiclePose(),
                                                    ekf.landmarkBlockMean(id).head<3>(), sensor);
    if (z_hat.head<2>().norm() > max_range + templateRadius(tpl) + options_.explain_distance_m) return;
    ++stats_.predicted;
    Vec3 placed = z_hat;
    const double view_change = viewChange(tpl, z_hat);
    // The uncertainty test comes before the view change: z_hat, hence the view change
    // measured from it, is meaningless when the prediction is metres off.
    const bool need_s = options_.max_prediction_std_m > 0 || (augmenter_ && options_.augment_above_std_m > 0);
    const Mat3 S = need_s ? predictionCov(ekf, id, sensor) : Mat3::Zero();
    const Eigen::SelfAdjointEigenSolver<Mat2> es(Mat2(S.topLeftCorner<2, 2>()));
    const double s_max = std::sqrt(std::max(es.eigenvalues()[1], 0.0));
    // Thesis 6.2: past augment_above_std_m the vehicle is no longer well correlated with
    // the landmark; the template gets the dense map around it. In-view test and explained
    // returns stay those of the template itself (what this landmark is).
    ScanTemplate augmented;
    const ScanTemplate* used = &tpl;
    const auto useAugmented = [&] {
        if (!augmenter_ || options_.augment_above_std_m <= 0 || s_max <= options_.augment_above_std_m) return;
        augmented = augmentedTemplate(ekf, id, tpl);
        const size_t added = augmented.sog.size() - tpl.sog.size();
        if (added == 0)
        {
            ++stats_.augment_empty;
            return;
        }
        ++stats_.augmented;
        stats_.augment_points += added;
        used = &augmented;
    };
    if (fractionInView(tpl, z_hat, max_range, fov) <= options_.in_view_fraction)
        ++stats_.out_of_view;
    else if (options_.max_prediction_std_m > 0 && s_max > options_.max_prediction_std_m)
    {
        if (options_.wide_search)
        {
            useAugmented();
            placed = observeWide(ekf, id, *used, pts, sensor, z_hat, S);
        }
        else
            ++stats_.prediction_uncertain;
    }
    else if (options_.max_view_change_m > 0 && view_change > options_.max_view_change_m)
        ++stats_.view_changed;
    else
    {
        useAugmented();
        placed = alignAndUpdate(ekf, id, tpl, used->sog, pts, sensor, max_range, fov, z_hat);
    }
    // Returns on a known landmark create nothing, whether it was observed or not (a
    // partial view must not become a second landmark on the same object).
    stats_.returns_explained += markExplained(tpl, placed, pts, options_.explain_distance_m, explained);
}

Mat3 ScanLandmarkMap::predictionCov(const ekf::EkfSlam& ekf, long id, const Vec3& sensor) const
{
    Mat3 Hv, Hl;
    ekf::poseLandmarkObservation(ekf.vehiclePose(), ekf.landmarkBlockMean(id).head<3>(), sensor, &Hv, &Hl);
    const auto o = static_cast<Eigen::Index>(ekf.landmarkBlock(id).offset);
    const auto P = ekf.cov();
    const Mat3 Pvl = P.block<3, 3>(0, o);
    const Mat3 S = Hv * P.topLeftCorner<3, 3>() * Hv.transpose() + Hl * P.block<3, 3>(o, o) * Hl.transpose() +
                   Hv * Pvl * Hl.transpose() + Hl * Pvl.transpose() * Hv.transpose();
    return 0.5 * (S + S.transpose());
}

Mat3 ScanLandmarkMap::viewCovariance(const Mat3& R, double d) const
{
    const double s_xy = options_.view_std_xy_m + options_.view_std_xy_per_m * d;
    const double s_phi = options_.view_std_phi + options_.view_std_phi_per_m * d;
    Mat3 out = R;
    out(0, 0) += s_xy * s_xy;
    out(1, 1) += s_xy * s_xy;
    out(2, 2) += s_phi * s_phi;
    return out;
}

void ScanLandmarkMap::createLandmarks(ekf::EkfSlam& ekf, const PointSet& pts, const Vec3& sensor,
                                      const std::vector<char>& explained)
{
    PointSet rest;
    for (size_t i = 0; i < pts.size(); ++i)
        if (!explained[i])
        {
            rest.add(pts.points[i], pts.covs[i]);
            rest.range.push_back(pts.range[i]);
            rest.bearing.push_back(pts.bearing[i]);
        }
    if (rest.size() < 3) return;
    size_t short_runs = 0;
    const auto segments = segmenter_.segment(rest, &short_runs);
    stats_.short_runs += short_runs;
    stats_.segments += segments.size();
    for (const auto& seg : segments)
    {
        PointSet s;
        for (size_t i : seg) s.add(rest.points[i], rest.covs[i]);
        Vec2 c = Vec2::Zero();
        for (const Vec2& p : s.points) c += p;
        c /= static_cast<double>(s.size());
        if (c.norm() > options_.max_creation_range_m)
        {
            ++stats_.segments_far;
            continue;
        }
        if (!hasOrientation(s, options_.min_spread_ratio))
        {
            ++stats_.segments_collinear;
            continue;
        }
        if (acceptance_.test(s) != SegmentAcceptance::Outcome::accepted) continue;
        ScanTemplate tpl = ScanTemplate::fromPoints(s);
        // The frame's observation covariance: the alignment of the template on the very
        // returns it was made of (their noise is what separates template and object).
        const AlignResult res = matcher_->align(tpl.sog, s, tpl.frame_in_sensor);
        if (!res.ok)
        {
            ++stats_.creation_failed;
            continue;
        }
        const long id = ekf.addPoseLandmark(tpl.frame_in_sensor, res.R, sensor);
        revisits_.created(id);
        templates_.emplace(id, std::move(tpl));
        ++stats_.created;
        if (keepsFirstScans()) first_scans_[id] = pts.points;
    }
    stats_.acceptance = acceptance_.stats().count;
}

}  // namespace hymm::scanslam
