#include "hymm/dynamic/SlamMotionHook.h"

#include <hymm/core/config_utils.h>

#include <cmath>
#include <stdexcept>

namespace hymm::dynamic
{
hymm::core::OptionTable SlamMotionHook::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.flag("enabled", enabled, "build the motion layers (Sec. 6.3) at all");
    t.flag("block_creation", block_creation, "no new landmarks from dynamic cells");
    t.real("creation_guard_m", creation_guard_m, "m", atLeast(0, 100),
           "without ids, an observation in a dynamic cell passes if a landmark is this close to it");
    t.flag("flag_landmarks", flag_landmarks, "mark landmarks that sit in dynamic cells");
    t.flag("prune_flagged", prune_flagged, "remove flagged landmarks no longer observed");
    t.flag("drop_flagged_observations", drop_flagged_observations,
           "observations of a flagged landmark (its id, or without ids the nearest landmark within creation_guard_m) are not used");
    t.real("prune_unseen_s", prune_unseen_s, "s", atLeast(0, 1e6), "unobserved this long before the removal");
    t.real("view_range_m", view_range_m, "m", above(0, 1000), "regions in a box of this half side are in view");
    t.real("view_fov_deg", view_fov_deg, "deg", above(0, 360),
           "a flagged landmark within view_range_m and this field of view that goes unobserved is gone");
    return t;
}

void SlamMotionHook::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
}

void SlamMotionHook::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
    detector.saveToConfigFile(cfg, "MotionDetector");
}

void SlamMotionHook::Options::loadAll(const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    loadFromConfigFile(cfg, s);
    detector.loadFromConfigFile(cfg, "MotionDetector");
}

SlamMotionHook::SlamMotionHook(const Options& options) : options_(options), detector_(options.detector)
{
}

long SlamMotionHook::nearestLandmark(const ekf::EkfSlam& ekf, const std::vector<long>& ids,
                                     const Eigen::Vector2d& p, double max_distance) const
{
    long best = -1;
    double best_d = max_distance;
    for (long id : ids)
    {
        if (ekf.landmarkBlock(id).dim != 2) continue;
        const double d = (ekf.landmarkMean(id) - p).norm();
        if (d <= best_d)
        {
            best = id;
            best_d = d;
        }
    }
    return best;
}

std::vector<ekf::RangeBearingObs> SlamMotionHook::filterObservations(
    const std::vector<ekf::RangeBearingObs>& obs, const ekf::EkfSlam& ekf,
    const ltr::RegionPartition* partition, const mrpt::poses::CPose3D& sensor, std::vector<size_t>& kept)
{
    kept.clear();
    std::vector<ekf::RangeBearingObs> out;
    out.reserve(obs.size());
    const bool check = options_.block_creation && partition && detector_.size() > 0;
    const bool drop = options_.drop_flagged_observations && !flagged_.empty();
    const Eigen::Vector3d v = ekf.vehiclePose();
    // Sensor pose in the global frame (planar part of the mounting).
    const double sx = v[0] + std::cos(v[2]) * sensor.x() - std::sin(v[2]) * sensor.y();
    const double sy = v[1] + std::sin(v[2]) * sensor.x() + std::cos(v[2]) * sensor.y();
    const double sphi = v[2] + sensor.yaw();
    const auto ids = check || drop ? ekf.landmarkIds() : std::vector<long>{};
    for (size_t i = 0; i < obs.size(); ++i)
    {
        const auto& o = obs[i];
        const Eigen::Vector2d p(sx + o.z[0] * std::cos(sphi + o.z[1]), sy + o.z[0] * std::sin(sphi + o.z[1]));
        const bool known = o.id >= 0 && ekf.hasLandmark(o.id);
        if (drop && flagged_.count(known    ? o.id
                                   : o.id < 0 ? nearestLandmark(ekf, ids, p, options_.creation_guard_m)
                                              : -1))
        {
            ++stats_.flagged_dropped;  // a landmark on a moving object corrects nothing
            continue;
        }
        bool pass = true;
        if (check && !known && detector_.isDynamic(*partition, p))
            // Without ids, it passes if it will associate with a landmark close to it.
            pass = o.id < 0 && nearestLandmark(ekf, ids, p, options_.creation_guard_m) >= 0;
        if (pass)
        {
            kept.push_back(i);
            out.push_back(o);
        }
        else
            ++stats_.creations_blocked;
    }
    return out;
}

void SlamMotionHook::noteUpdate(const ekf::UpdateReport& report, double t)
{
    for (long id : report.assigned_ids)
        if (id >= 0) last_seen_[id] = t;
}

std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> SlamMotionHook::markedBox(
    const ltr::RegionPartition& partition, const Eigen::Vector2d& vehicle) const
{
    // isDynamic(p) reads only the regions the partition's grid lists in p's cell, and a
    // region is listed in the cells its current triangle's bounding box meets: a landmark
    // in the view box can be flagged only within one grid cell of the bounding box of a
    // region with a marked cell, listed in the cells of the view box. The margins (one
    // cell, 1 m) keep the bound safe from rounding; the exact tests follow.
    const double c = partition.options().grid_cell_size_m;
    const Eigen::Vector2d pad = Eigen::Vector2d::Constant(options_.view_range_m + c + 1.0);
    std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> box;
    const auto extend = [&box](const ltr::TriangleFrame::Vertices& tri) {
        for (const auto& q : tri)
        {
            if (!box) box.emplace(q, q);
            box->first = box->first.cwiseMin(q);
            box->second = box->second.cwiseMax(q);
        }
    };
    for (long id : partition.regionsInBox(vehicle - pad, vehicle + pad))
        if (detector_.hasMarks(id)) extend(partition.region(id).current);
    // The same for the fallback tiles: isDynamic(p) reads the tiles of the anchors the
    // grid lists within the tiles' reach of p.
    if (detector_.tiles() > 0)
    {
        const Eigen::Vector2d reach = pad + Eigen::Vector2d::Constant(detector_.tileReach());
        for (const auto& tri : detector_.markedTileTriangles(
                 partition, partition.regionsInBox(vehicle - reach, vehicle + reach)))
            extend(tri);
    }
    if (box)
    {
        box->first.array() -= c + 1.0;
        box->second.array() += c + 1.0;
    }
    return box;
}

void SlamMotionHook::flagLandmarks(const ltr::RegionPartition& partition, const ekf::EkfSlam& ekf,
                                   const Eigen::Vector2d& vehicle)
{
    const auto box = markedBox(partition, vehicle);
    if (!box) return;  // no marked region near the view: no landmark can be flagged
    // One pass over the state vector (no look-up per landmark): every EKF update moves
    // every landmark's mean, so no index of positions kept across steps is exact.
    const Eigen::VectorXd& x = ekf.mean();
    for (const auto& b : ekf.layout().blocks())
    {
        if (b.dim != 2) continue;
        const Eigen::Vector2d p = x.segment<2>(static_cast<Eigen::Index>(b.offset));
        if ((p.array() < box->first.array()).any() || (p.array() > box->second.array()).any()) continue;
        if ((p - vehicle).cwiseAbs().maxCoeff() > options_.view_range_m) continue;
        if (!flagged_.count(b.id) && detector_.isDynamic(partition, p))
        {
            flagged_.insert(b.id);
            ++stats_.landmarks_flagged;
        }
    }
}

std::vector<long> SlamMotionHook::afterFrame(const dense::HybridMetricMap& map,
                                             const ltr::RegionPartition& partition, ekf::EkfSlam& ekf,
                                             double t)
{
    const Eigen::Vector3d v = ekf.vehiclePose();
    const Eigen::Vector2d r = Eigen::Vector2d::Constant(options_.view_range_m);
    const Eigen::Vector2d lo = v.head<2>() - r, hi = v.head<2>() + r;
    const auto rep = detector_.step(map, partition.regionsInBox(lo, hi),
                                    detector_.options().fallback_tiles && map.options().fallback_max_distance_m > 0
                                        ? map.fallbackTilesInBox(partition, lo, hi)
                                        : std::vector<dense::FallbackTileKey>{},
                                    t);
    stats_.fast_differencings += rep.fast_differenced;
    stats_.slow_differencings += rep.slow_differenced;
    std::vector<long> removed;
    // Landmarks that left the filter leave the bookkeeping.
    for (auto it = flagged_.begin(); it != flagged_.end();)
        it = ekf.hasLandmark(*it) ? std::next(it) : flagged_.erase(it);
    if (!options_.flag_landmarks) return removed;
    flagLandmarks(partition, ekf, v.head<2>());
    if (!options_.prune_flagged) return removed;
    for (auto it = flagged_.begin(); it != flagged_.end();)
    {
        // Only a landmark in the sensor's view and not observed counts as gone; one
        // merely out of view keeps its place.
        const Eigen::Vector2d d = ekf.landmarkMean(*it) - v.head<2>();
        const double bearing = std::remainder(std::atan2(d.y(), d.x()) - v[2], 2 * M_PI);
        const bool in_view = d.norm() <= options_.view_range_m &&
                             std::abs(bearing) <= 0.5 * options_.view_fov_deg * M_PI / 180.0;
        const auto seen = last_seen_.find(*it);
        const double last = seen == last_seen_.end() ? -1e300 : seen->second;
        if (in_view && t - last > options_.prune_unseen_s)
        {
            ekf.removeLandmark(*it);
            removed.push_back(*it);
            last_seen_.erase(*it);
            it = flagged_.erase(it);
            ++stats_.landmarks_pruned;
        }
        else
            ++it;
    }
    return removed;
}

}  // namespace hymm::dynamic
