/**
 * @file ScanLandmarkWide.cpp
 * @brief ScanLandmarkMap::observeWide: the re-observation of a template whose predicted
 *        pose is too uncertain for the local matchers (a loop closure after drift).
 *        Wide correlative search over the +-3 sigma window of the prediction (capped),
 *        accepted only when distinctive (WideSearch.h), refined by the normal matcher,
 *        the view-change guard applied to the refined pose, and fused through the
 *        usual NN gate with S = H P H^T + R (R with the viewpoint term). Every outcome
 *        is counted in Stats::wide.
 */
#include <mrpt/math/wrap2pi.h>

#include <cmath>

#include "hymm/scanslam/ScanLandmarkMap.h"

namespace hymm::scanslam
{
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
    // +-3 sigma of the prediction per axis (the window is axis-aligned in the sensor frame).
    const Vec3 half = 3.0 * S.diagonal().cwiseMax(0.0).cwiseSqrt();
    if (half.x() > options_.wide_max_xy_m || half.y() > options_.wide_max_xy_m || half.z() > options_.wide_max_phi)
    {
        ++stats_.wide["window_too_large"];
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
    const WideResult w = wideSearch(tpl.sog, pts, z_hat, half, options_.wide);
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
    if (options_.max_view_change_m > 0 &&
        (res.z.head<2>() - tpl.frame_in_sensor.head<2>()).norm() > options_.max_view_change_m)
    {
        ++stats_.wide["view_changed"];
        return z_hat;
    }
    if (options_.wide_confirm_scans > 0 && !confirmWide(ekf, id, res.z, sensor)) return z_hat;
    ++stats_.aligned;
    const Mat3 R = viewCovariance(res.R, tpl.frame_in_sensor, res.z);
    const auto rep = ekf.updatePoseLandmark(id, res.z, R, sensor, options_.gate_prob, options_.wide_update_iterations);
    using O = ekf::PoseUpdateReport::Outcome;
    last_aligned_.push_back({id, res.z, R, z_hat, rep.outcome == O::updated, true});
    switch (rep.outcome)
    {
        case O::updated:
            ++stats_.updated;
            ++stats_.wide["closed"];
            return res.z;
        case O::gated: ++stats_.wide["gated"]; break;
        case O::numeric: ++stats_.wide["numeric"]; break;
        case O::invalid: ++stats_.wide["invalid"]; break;
    }
    return z_hat;
}

}  // namespace hymm::scanslam
