/**
 * @file ScanLandmarkAlign.cpp
 * @brief The alignment of one template and its fusion (ScanLandmarkMap::alignAndUpdate),
 *        and the template augmented with the dense map around it (thesis 6.2,
 *        ScanLandmarkMap::augmentedTemplate).
 */
#include <hymm/ekf/pose_landmark_model.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

#include "hymm/scanslam/ScanLandmarkMap.h"

namespace hymm::scanslam
{
void ScanLandmarkMap::countUpdate(long id, bool wide)
{
    ++stats_.updated;
    revisits_.updated(id, wide, options_.revisit_gap_s);
}

void declareViewCorrKeys(core::OptionTable& t, ScanLandmarkMap::Options& o)
{
    using namespace hymm::core;
    using M = ScanLandmarkMap::Options::ViewCorrModel;
    t.real("view_corr_share", o.view_corr_share, "", between(0, 1),
           "correlated share c of an alignment's error between nearby viewpoints (0: independent)");
    t.real("view_corr_length_m", o.view_corr_length_m, "m", above(0, 10000),
           "correlation length L of that share over the viewpoint");
    t.real("view_corr_pass_fraction", o.view_corr_pass_fraction, "", between(0, 1),
           "state: the share counted against earlier passes' viewpoints, as a fraction of view_corr_share (0: a new pass is independent)");
    t.choice("view_corr_model", o.view_corr_model, {{"inflate", M::Inflate}, {"state", M::State}},
             "that share as a larger R (inflate) or as a Gauss-Markov state of each template's apparent pose (state)");
    t.real("view_corr_drop_lengths", o.view_corr_drop_lengths, "", above(0, 1000),
           "state: an apparent pose is marginalised out once the sensor is this many L from its last viewpoint");
}

size_t ScanLandmarkMap::fusedViews(long id) const
{
    const auto it = fused_views_.find(id);
    return it != fused_views_.end() ? it->second.size() : 0;
}

double ScanLandmarkMap::viewCorrelationFactor(long id, const Vec2& view, double c, size_t n_views) const
{
    const auto it = fused_views_.find(id);
    if (c <= 0 || it == fused_views_.end()) return 1.0;
    const size_t n = std::min(n_views, it->second.size());
    if (n == 0) return 1.0;
    double d2 = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < n; ++i) d2 = std::min(d2, (it->second[i] - view).squaredNorm());
    // f = (1 + rho) / (1 - rho) = coth(delta / 2L), rho = exp(-delta / L).
    const double x = std::sqrt(d2) / (2 * options_.view_corr_length_m);
    const double f = x > 0 ? 1.0 / std::tanh(x) : std::numeric_limits<double>::infinity();
    return std::min(1.0 + c * (f - 1.0), kMaxViewCorrFactor);
}

Vec3 ScanLandmarkMap::alignAndUpdate(ekf::EkfSlam& ekf, long id, const ScanTemplate& tpl, const PointSet& aligned,
                                     const PointSet& pts, const Vec3& sensor, double max_range, double fov,
                                     const Vec3& z_hat)
{
    const AlignResult res = matcher_->align(
        options_.visible_bin > 0
            ? visiblePart(aligned, z_hat, max_range, fov, options_.visible_bin, options_.visible_depth_tol_m)
            : aligned,
        pts, z_hat);
    if (!res.ok)
    {
        ++stats_.align_failed[res.failure];
        return z_hat;
    }
    ++stats_.aligned;
    // The viewpoint: the sensor's position in the template frame, as aligned.
    const Vec2 view = inverse(res.z).head<2>();
    const Mat3 Rv = viewCovariance(res.R, viewChange(tpl, z_hat));
    // view_corr_model = state: the correlated share c of the error is in the apparent pose
    // block, the update takes the independent rest.
    const bool state = options_.view_corr_share > 0 && options_.view_corr_model == Options::ViewCorrModel::State;
    Mat3 R;
    long target = id;
    if (state)
    {
        // Viewpoints of earlier passes (fused before this apparent pose existed) count as
        // in the inflate model, with the share view_corr_pass_fraction c: the state
        // carries the correlation within a pass only.
        const auto a = apparent_.find(id);
        const size_t past = a != apparent_.end() ? a->second.first_view : fusedViews(id);
        const double pass_share = options_.view_corr_pass_fraction * options_.view_corr_share;
        const Mat3 Rp = viewCorrelationFactor(id, view, pass_share, past) * Rv;
        target = apparentBlock(ekf, id, view, Rp, sensor);
        R = (1 - options_.view_corr_share) * Rp;
    }
    else
        R = viewCorrelationFactor(id, view, options_.view_corr_share) * Rv;
    const auto rep = ekf.updatePoseLandmark(target, res.z, R, sensor, options_.gate_prob, options_.update_iterations);
    using O = ekf::PoseUpdateReport::Outcome;
    last_aligned_.push_back({id, res.z, R, z_hat, rep.outcome == O::updated});
    switch (rep.outcome)
    {
        case O::updated:
            countUpdate(id, false);
            if (options_.view_corr_share > 0) fused_views_[id].push_back(view);
            return res.z;
        case O::gated: ++stats_.gated; break;
        case O::numeric: ++stats_.update_numeric; break;
        case O::invalid: ++stats_.update_invalid; break;
    }
    return z_hat;
}

long ScanLandmarkMap::apparentBlock(ekf::EkfSlam& ekf, long id, const Vec2& view, const Mat3& R, const Vec3& sensor)
{
    // The stationary covariance of the apparent pose's error, c R in the global frame: the
    // observation's Jacobian in the landmark pose is a rotation (pose_landmark_model.h),
    // so that is c H_l^-1 R H_l^-T.
    Mat3 Hv, Hl;
    ekf.poseObservationJacobians(id, sensor, Hv, Hl);
    const Mat3 Hi = Hl.inverse();
    Mat3 sigma = options_.view_corr_share * Hi * R * Hi.transpose();
    sigma = (0.5 * (sigma + sigma.transpose())).eval();
    // Every entry's block is alive here: dropApparentBlocks (at the start of the scan) and
    // dropApparentBlock (before a wide update) remove both together.
    const auto it = apparent_.find(id);
    if (it != apparent_.end())
    {
        // b <- rho b + w over the viewpoint change since the block's last step.
        const double rho = std::exp(-(view - it->second.view).norm() / options_.view_corr_length_m);
        ekf.relaxBlockTowards(it->second.block, id, rho, (1 - rho * rho) * sigma);
        it->second.view = view;
        return it->second.block;
    }
    const long block = ekf.addBlockCopy(id, sigma);
    apparent_[id] = {block, view, fusedViews(id)};
    return block;
}

void ScanLandmarkMap::dropApparentBlocks(ekf::EkfSlam& ekf, const Vec3& sensor)
{
    const double far = options_.view_corr_drop_lengths * options_.view_corr_length_m;
    for (auto it = apparent_.begin(); it != apparent_.end();)
    {
        bool drop = !templates_.count(it->first) || !ekf.hasLandmark(it->second.block);
        if (!drop)
        {
            // The sensor's position in the template frame at the current estimates.
            const Vec3 z = ekf::poseLandmarkObservation(ekf.vehiclePose(), ekf.landmarkBlockMean(it->first).head<3>(),
                                                        sensor);
            drop = (inverse(z).head<2>() - it->second.view).norm() > far;
        }
        it = drop ? dropApparentBlock(ekf, it) : std::next(it);
    }
}

std::map<long, ScanLandmarkMap::Apparent>::iterator ScanLandmarkMap::dropApparentBlock(
    ekf::EkfSlam& ekf, std::map<long, Apparent>::iterator it)
{
    if (it == apparent_.end()) return it;
    if (ekf.hasLandmark(it->second.block)) ekf.removeLandmark(it->second.block);
    return apparent_.erase(it);
}

ScanTemplate ScanLandmarkMap::augmentedTemplate(const ekf::EkfSlam& ekf, long id, const ScanTemplate& tpl) const
{
    if (!augmenter_ || tpl.sog.empty()) return tpl;
    // The template's bounds in its frame, grown by the margin.
    Vec2 lo = tpl.sog.points.front(), hi = lo;
    for (const Vec2& p : tpl.sog.points)
    {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    lo.array() -= options_.augment_margin_m;
    hi.array() += options_.augment_margin_m;
    // That box placed at the filter's estimate of the frame, as a global box for the query.
    const Vec3 frame = ekf.landmarkBlockMean(id).head<3>();
    Vec2 glo = Vec2::Constant(std::numeric_limits<double>::infinity()), ghi = -glo;
    for (const Vec2& c : {lo, hi, Vec2(lo.x(), hi.y()), Vec2(hi.x(), lo.y())})
    {
        const Vec2 g = transformPoint(frame, c);
        glo = glo.cwiseMin(g);
        ghi = ghi.cwiseMax(g);
    }
    const PointSet dense = augmenter_(glo, ghi);
    // Into the landmark frame: p_l = R^T (p - t), C_l = R^T C R; only those in the box.
    const Mat2 Rt = rotation(frame.z()).transpose();
    std::vector<size_t> inside;
    std::vector<Vec2> local(dense.size());
    for (size_t i = 0; i < dense.size(); ++i)
    {
        local[i] = Rt * (dense.points[i] - frame.head<2>());
        const Vec2& q = local[i];
        if (q.allFinite() && q.x() >= lo.x() && q.x() <= hi.x() && q.y() >= lo.y() && q.y() <= hi.y())
            inside.push_back(i);
    }
    ScanTemplate out = tpl;
    const size_t n = std::min(inside.size(), options_.augment_max_points);
    for (size_t k = 0; k < n; ++k)
    {
        // Evenly thinned: the k-th of n picks spread over all of them.
        const size_t i = inside[k * inside.size() / n];
        out.sog.add(local[i], Rt * dense.covs[i] * Rt.transpose());
    }
    return out;
}

}  // namespace hymm::scanslam
