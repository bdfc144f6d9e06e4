/**
 * @file ScanLandmarkMerge.cpp
 * @brief ScanLandmarkMap::mergeDuplicates: two landmarks on one object become one. A
 *        landmark aligned in this scan is checked against every landmark whose template,
 *        placed at the filter's estimates, overlaps its own. The newer template is aligned
 *        with the older one, the filter fuses that relative pose
 *        (EkfSlam::updateRelativePose) and the newer block is marginalised out, so what it
 *        was observed to be reaches the older one through their correlation.
 */
#include <hymm/ekf/EkfSlam.h>

#include <algorithm>
#include <set>

#include "hymm/scanslam/ScanLandmarkMap.h"

namespace hymm::scanslam
{
namespace
{
/** Share of the smaller set's points within d of a point of the other. */
double overlap(const std::vector<Vec2>& a, const std::vector<Vec2>& b, double d)
{
    const auto& small = a.size() <= b.size() ? a : b;
    const auto& large = a.size() <= b.size() ? b : a;
    if (small.empty()) return 0;
    size_t near = 0;
    for (const Vec2& p : small)
        near += std::any_of(large.begin(), large.end(), [&](const Vec2& q) { return (p - q).squaredNorm() <= d * d; });
    return static_cast<double>(near) / static_cast<double>(small.size());
}
}  // namespace

void ScanLandmarkMap::mergeDuplicates(ekf::EkfSlam& ekf)
{
    // Each landmark aligned in this scan against every other landmark whose template,
    // placed at the filter's estimates, overlaps its own: an older landmark not located
    // again (so the newer one was made) may be anywhere in the map.
    std::set<long> seen;
    for (const AlignedObservation& a : last_aligned_)
        if (a.updated && templates_.count(a.id)) seen.insert(a.id);
    if (seen.empty()) return;
    struct Placed
    {
        long id;
        Vec3 x;
        double radius;
    };
    std::vector<Placed> all;  // every template's frame and reach, once per scan
    all.reserve(templates_.size());
    for (const auto& [id, tpl] : templates_)
        all.push_back({id, ekf.landmarkBlockMean(id).head<3>(), templateRadius(tpl)});
    std::set<std::pair<long, long>> pairs;  // (keep, drop): the older landmark stays
    for (const Placed& a : all)
    {
        if (!seen.count(a.id)) continue;
        const std::vector<Vec2> pa = transformedPoints(templates_.at(a.id).sog.points, a.x);
        for (const Placed& o : all)
        {
            if (o.id == a.id || (o.x.head<2>() - a.x.head<2>()).norm() > a.radius + o.radius + options_.explain_distance_m)
                continue;
            const std::vector<Vec2> po = transformedPoints(templates_.at(o.id).sog.points, o.x);
            if (overlap(pa, po, options_.explain_distance_m) >= options_.merge_min_overlap)
                pairs.emplace(std::min(a.id, o.id), std::max(a.id, o.id));
        }
    }
    std::set<long> gone;
    for (const auto& [keep, drop] : pairs)
    {
        if (gone.count(keep) || gone.count(drop)) continue;
        const auto last = merge_last_.find({keep, drop});
        if (last != merge_last_.end() && stats_.scans < last->second + options_.merge_retry_scans) continue;
        if (mergePair(ekf, keep, drop))
            gone.insert(drop);
        else
            merge_last_[{keep, drop}] = stats_.scans;
    }
}

bool ScanLandmarkMap::mergePair(ekf::EkfSlam& ekf, long keep, long drop)
{
    ++stats_.merge_candidates;
    const ScanTemplate& tk = templates_.at(keep);
    const ScanTemplate& td = templates_.at(drop);
    const Vec3 xk = ekf.landmarkBlockMean(keep).head<3>(), xd = ekf.landmarkBlockMean(drop).head<3>();
    // The kept frame in the dropped one's (the filter's guess, refined by aligning the two
    // templates): the observation of `keep` from `drop`.
    const AlignResult res = matcher_->align(tk.sog, td.sog, compose(inverse(xd), xk));
    if (!res.ok)
    {
        ++stats_.merge_align_failed;
        return false;
    }
    // Viewpoint term (view_std_*) for the distance between where the two were made: their
    // sensors' poses at creation, through the filter's frames.
    const double d = (compose(xk, inverse(tk.frame_in_sensor)).head<2>() -
                      compose(xd, inverse(td.frame_in_sensor)).head<2>()).norm();
    const Mat3 R = viewCovariance(res.R, d);
    const auto rep = ekf.updateRelativePose(drop, keep, res.z, R, options_.gate_prob, options_.wide_update_iterations);
    if (rep.outcome != ekf::PoseUpdateReport::Outcome::updated)
    {
        ++stats_.merge_gated;
        return false;
    }
    ekf.removeLandmark(drop);
    templates_.erase(drop);  // its bookkeeping goes at the next scan (processScan)
    ++stats_.merged;
    return true;
}

}  // namespace hymm::scanslam
