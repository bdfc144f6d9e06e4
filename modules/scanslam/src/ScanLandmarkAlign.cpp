/**
 * @file ScanLandmarkAlign.cpp
 * @brief The alignment of one template and its fusion (ScanLandmarkMap::alignAndUpdate),
 *        and the template augmented with the dense map around it (thesis 6.2,
 *        ScanLandmarkMap::augmentedTemplate).
 */
#include <algorithm>
#include <limits>

#include "hymm/scanslam/ScanLandmarkMap.h"

namespace hymm::scanslam
{
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
    const Mat3 R = viewCorrelationFactor(id, view) * viewCovariance(res.R, viewChange(tpl, z_hat));
    const auto rep = ekf.updatePoseLandmark(id, res.z, R, sensor, options_.gate_prob, options_.update_iterations);
    using O = ekf::PoseUpdateReport::Outcome;
    last_aligned_.push_back({id, res.z, R, z_hat, rep.outcome == O::updated});
    switch (rep.outcome)
    {
        case O::updated:
            ++stats_.updated;
            if (options_.view_corr_share > 0) fused_views_[id].push_back(view);
            return res.z;
        case O::gated: ++stats_.gated; break;
        case O::numeric: ++stats_.update_numeric; break;
        case O::invalid: ++stats_.update_invalid; break;
    }
    return z_hat;
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
