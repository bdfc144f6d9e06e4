/**
 * @file ScanLandmarkWide.cpp
 * @brief ScanLandmarkMap::observeWide: the re-observation of a template whose predicted
 *        pose is too uncertain for the local matchers (a loop closure after drift).
 *        Wide correlative search over the +-3 sigma window of the prediction (capped,
 *        cut to the template's viewpoints with wide_view_window_m), accepted only when
 *        distinctive (WideSearch.h), refined by the normal matcher, the view-change
 *        guard applied to the refined pose, confirmed by another template, and fused
 *        through the usual NN gate with S = H P H^T + R (R with the viewpoint term).
 *        Every outcome is counted in Stats::wide. The wide_* keys of [ScanLandmarks].
 */
#include <hymm/core/OptionTable.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>

#include "hymm/scanslam/ScanLandmarkMap.h"

namespace hymm::scanslam
{
namespace
{
/** The wide search's window (centre, half extents) for a template made at `made` (its
 *  frame in the sensor frame then) and predicted at z_hat with covariance S: the
 *  prediction's +-3 sigma box, cut, with wide_view_window_m > 0, to the poses that place
 *  the frame within that distance (x, y) and wide_view_window_phi (heading) of `made`:
 *  the viewpoints from which the template shows the faces it was made of. Returns the
 *  reason it is refused (view_elsewhere: the two do not meet; window_too_large: beyond
 *  the caps), nullptr when it is searched. */
const char* searchWindow(const Vec3& z_hat, const Mat3& S, const Vec3& made, const ScanLandmarkMap::Options& o,
                         Vec3& center, Vec3& half)
{
    const Vec3 h = 3.0 * S.diagonal().cwiseMax(0.0).cwiseSqrt();
    center = z_hat;
    half = h;
    if (o.wide_view_window_m > 0)
    {
        Vec3 lo = z_hat - h, hi = z_hat + h;
        lo.head<2>() = lo.head<2>().cwiseMax(made.head<2>() - Vec2::Constant(o.wide_view_window_m));
        hi.head<2>() = hi.head<2>().cwiseMin(made.head<2>() + Vec2::Constant(o.wide_view_window_m));
        // made's heading on z_hat's branch of the angle.
        const double m = z_hat.z() + mrpt::math::wrapToPi(made.z() - z_hat.z());
        lo.z() = std::max(lo.z(), m - o.wide_view_window_phi);
        hi.z() = std::min(hi.z(), m + o.wide_view_window_phi);
        if ((hi - lo).minCoeff() < 0) return "view_elsewhere";
        center = 0.5 * (lo + hi);
        half = 0.5 * (hi - lo);
    }
    if (half.x() > o.wide_max_xy_m || half.y() > o.wide_max_xy_m || half.z() > o.wide_max_phi)
        return "window_too_large";
    return nullptr;
}
}  // namespace

/** The wide-search keys of [ScanLandmarks] (README: "Loop closure by a wide search"). */
void declareWideKeys(core::OptionTable& t, ScanLandmarkMap::Options& o)
{
    using namespace hymm::core;
    t.flag("wide_search", o.wide_search,
           "templates refused by max_prediction_std_m are searched over their +-3 sigma window");
    t.real("wide_coarse_step_m", o.wide.coarse_step_m, "m", above(0, 100), "wide search: level-A step and likelihood std");
    t.real("wide_fine_step_m", o.wide.fine_step_m, "m", above(0, 100), "wide search: level-B step");
    t.real("wide_fine_sigma_m", o.wide.fine_sigma_m, "m", above(0, 100), "wide search: level-B likelihood std");
    t.integer("wide_candidates", o.wide.candidates, "", 1, 1000, "wide search: level-A peaks refined");
    t.integer("wide_max_points", o.wide.max_points, "", 3, 100000, "wide search: template points scored (subsample)");
    t.real("wide_peak_separation_m", o.wide.peak_separation_m, "m", above(0, 1000),
           "wide search: peaks moving the template less than this are one");
    t.real("wide_max_ambiguity", o.wide.max_ambiguity, "", between(0, 1),
           "wide search: second separate peak's goodness / best's below this");
    t.real("wide_min_matched_fraction", o.wide.min_matched_fraction, "", between(0, 1),
           "wide search: template points within the gate at the best pose");
    t.real("wide_max_xy_m", o.wide_max_xy_m, "m", above(0, 10000), "wide search: largest +-3 sigma half window in x, y");
    t.real("wide_max_phi_deg", o.wide_max_phi, "deg", above(0, 180), "wide search: largest half window in angle", M_PI / 180);
    t.integer("wide_max_per_scan", o.wide_max_per_scan, "", 1, 1000, "wide searches per scan");
    t.integer("wide_retry_scans", o.wide_retry_scans, "", 1, 1000000, "scans between wide searches of one template");
    t.integer("wide_confirm_scans", o.wide_confirm_scans, "", 0, 1000000,
              "wide answers fused only when another template's within this many scans agrees (0: at once)");
    t.real("wide_confirm_xy_m", o.wide_confirm_xy_m, "m", above(0, 1000), "agreement of the implied vehicle corrections in x, y");
    t.real("wide_confirm_phi_deg", o.wide_confirm_phi, "deg", above(0, 180), "and in heading", M_PI / 180);
    t.real("wide_view_window_m", o.wide_view_window_m, "m", atLeast(0, 1000),
           "> 0: the wide search only places a template within this of where it was made in the sensor frame");
    t.real("wide_view_window_phi_deg", o.wide_view_window_phi, "deg", above(0, 180),
           "and within this of its heading then", M_PI / 180);
    t.real("wide_cov_inflation", o.wide_cov_inflation, "", atLeast(1, 1e6),
           "a wide answer's covariance (with the viewpoint term) times this before its update");
    t.real("wide_max_free_conflict", o.wide_max_free_conflict, "", atLeast(0, 1),
           "a wide answer is refused when more of its scan's returns than this lie in the free space of the "
           "template's first scan, or the other way round (1: off)");
    t.real("wide_free_margin_m", o.wide_free_margin_m, "m", above(0, 100),
           "a return conflicts when this far in front of the other scan's return on its bearing");
}

namespace
{
/** Fewer returns tested in a direction than this say nothing about the place. */
constexpr size_t kMinFreeSpaceTested = 20;
}  // namespace

bool ScanLandmarkMap::refusedByFirstScan(long id, const ScanTemplate& tpl, const PointSet& pts, const Vec3& z)
{
    const auto first = first_scans_.find(id);
    if (first == first_scans_.end()) return false;
    // The current sensor in the frame of the scan the template was made from.
    const Vec3 now_in_first = compose(tpl.frame_in_sensor, inverse(z));
    if (freeSpaceConflict(first->second, pts.points, now_in_first, options_.wide_free_margin_m, M_PI / 180)
            .share(kMinFreeSpaceTested) <= options_.wide_max_free_conflict)
        return false;
    ++stats_.wide["free_space_conflict"];
    return true;
}

bool ScanLandmarkMap::confirmWide(const ekf::EkfSlam& ekf, long id, const Vec3& z, const Vec3& sensor)
{
    // The vehicle pose that would make landmark `id` appear at z, as a correction of the
    // estimate (global x, y, phi); odometry changes it little over a few scans.
    const Vec3 implied = compose(compose(ekf.landmarkBlockMean(id).head<3>(), inverse(z)), inverse(sensor));
    Vec3 c = implied - ekf.vehiclePose();
    c.z() = mrpt::math::wrapToPi(c.z());
    const WidePending& p = wide_pending_;
    const bool recent = p.id >= 0 && stats_.scans <= p.scan + options_.wide_confirm_scans;
    if (recent && p.id != id && (c - p.correction).head<2>().norm() < options_.wide_confirm_xy_m &&
        std::abs(mrpt::math::wrapToPi(c.z() - p.correction.z())) < options_.wide_confirm_phi)
    {
        wide_pending_ = WidePending{};
        ++stats_.wide["confirmed"];
        return true;
    }
    if (recent && p.id != id) ++stats_.wide["disagreed"];
    wide_pending_ = WidePending{id, stats_.scans, c};
    ++stats_.wide["pending"];
    return false;
}

Vec3 ScanLandmarkMap::observeWide(ekf::EkfSlam& ekf, long id, const ScanTemplate& tpl, const PointSet& pts,
                                  const Vec3& sensor, const Vec3& z_hat, const Mat3& S)
{
    // +-3 sigma of the prediction per axis (the window is axis-aligned in the sensor
    // frame), cut to the viewpoints of wide_view_window_m.
    Vec3 center, half;
    if (const char* refused = searchWindow(z_hat, S, tpl.frame_in_sensor, options_, center, half))
    {
        ++stats_.wide[refused];
        return z_hat;
    }
    const auto last = wide_last_.find(id);
    if (wide_this_scan_ >= options_.wide_max_per_scan ||
        (last != wide_last_.end() && stats_.scans < last->second + options_.wide_retry_scans))
    {
        ++stats_.wide["deferred"];
        return z_hat;
    }
    ++wide_this_scan_;
    wide_last_[id] = stats_.scans;
    const WideResult w = wideSearch(tpl.sog, pts, center, half, options_.wide);
    if (!w.ok)
    {
        ++stats_.wide[w.failure];
        return z_hat;
    }
    // The wide answer is good to a level-B step; the matcher gives the pose and its R.
    const AlignResult res = matcher_->align(tpl.sog, pts, w.z);
    if (!res.ok)
    {
        ++stats_.wide[std::string("refine.") + res.failure];
        return z_hat;
    }
    if (options_.max_view_change_m > 0 && viewChange(tpl, res.z) > options_.max_view_change_m)
    {
        ++stats_.wide["view_changed"];
        return z_hat;
    }
    if (refusedByFirstScan(id, tpl, pts, res.z)) return z_hat;
    if (options_.wide_confirm_scans > 0 && !confirmWide(ekf, id, res.z, sensor)) return z_hat;
    ++stats_.aligned;
    const Mat3 R = options_.wide_cov_inflation * viewCovariance(res.R, viewChange(tpl, res.z));
    // view_corr_model = state: a wide answer observes the template's pose with its whole
    // R; the apparent pose of an earlier pass (if still held) is marginalised out first.
    dropApparentBlock(ekf, apparent_.find(id));
    const auto rep = ekf.updatePoseLandmark(id, res.z, R, sensor, options_.gate_prob, options_.wide_update_iterations);
    using O = ekf::PoseUpdateReport::Outcome;
    last_aligned_.push_back({id, res.z, R, z_hat, rep.outcome == O::updated, true});
    switch (rep.outcome)
    {
        case O::updated:
            countUpdate(id, true);
            ++stats_.wide["closed"];
            return res.z;
        case O::gated: ++stats_.wide["gated"]; break;
        case O::numeric: ++stats_.wide["numeric"]; break;
        case O::invalid: ++stats_.wide["invalid"]; break;
    }
    return z_hat;
}

}  // namespace hymm::scanslam
