/**
 * @file DenseSlamLandmarks.cpp
 * @brief Steps 2-3 of the pipeline (DenseSlam.h, thesis Fig. 3.3): the landmark sources'
 *        observations of a frame, the same-object rule between scan sources, the EKF
 *        update and the bookkeeping of which source observed each landmark.
 */
#include "hymm/denseslam/DenseSlam.h"
#include "hymm/denseslam/dense_gaussians.h"

#include <mrpt/system/datetime.h>

#include <algorithm>
#include <cmath>

namespace hymm::denseslam
{
namespace
{
Eigen::Vector2d featurePoint(const ekf::RangeBearingObs& f)
{
    return f.z(0) * Eigen::Vector2d(std::cos(f.z(1)), std::sin(f.z(1)));
}

// A feature is the object of an earlier source's feature when their beams overlap (a tree
// the tree extractor saw on a reflector's tape) or their centres are within `distance` (a
// cluster split by a dropout, tape on a post against a trunk: one place for the filter
// either way).
bool sameObject(const ekf::RangeBearingObs& f, const std::pair<size_t, size_t>& f_beams,
                const ekf::RangeBearingObs& earlier, const std::pair<size_t, size_t>& earlier_beams,
                double distance)
{
    if (f_beams.first <= earlier_beams.second && earlier_beams.first <= f_beams.second) return true;
    return (featurePoint(f) - featurePoint(earlier)).norm() <= distance;
}

}  // namespace

const ScanLandmarksSource* DenseSlam::scanLandmarks() const
{
    for (const auto& s : sources_)
        if (const auto* p = dynamic_cast<const ScanLandmarksSource*>(s.get())) return p;
    return nullptr;
}

std::vector<std::pair<std::string, size_t>> DenseSlam::scanSourceCounters() const
{
    std::vector<std::pair<std::string, size_t>> out;
    for (const auto& s : sources_)
        for (const auto& [k, n] : s->counters()) out.emplace_back(s->name() + "." + k, n);
    if (scan_odometry_)
        for (const auto& [k, n] : scan_odometry_->stats().list()) out.emplace_back("scan_odometry." + k, n);
    if (options_.turn_bias_state && scan_odometry_)
    {
        const TurnBiasStats& t = turn_bias_stats_;
        for (const auto& [k, n] : {std::pair<const char*, size_t>{"copies", t.copies}, {"fused", t.fused},
                                   {"gated", t.gated}, {"failed", t.failed}})
            out.emplace_back(std::string("turn_bias_state.") + k, n);
    }
    return out;
}

void DenseSlam::processScanSources(const mrpt::obs::CObservation2DRangeScan& scan)
{
    if (sources_.empty()) return;
    core::TimedSection tle(profiler_, "denseslam.3_scan_sources");
    for (auto& src : sources_)
    {
        const size_t before = src->mapChanges();
        // Scan landmarks read the dense map around a template when its alignment needs
        // more than one scan's points (thesis 6.2; [ScanLandmarks] augment_above_std_m).
        // Installed per call: the function reads this object's current partition.
        auto* scan_lm = dynamic_cast<ScanLandmarksSource*>(src.get());
        if (scan_lm && partition_ && hybrid_ && scan_lm->map().options().augment_above_std_m > 0)
        {
            const double point_std = scan_lm->map().options().noise.std_range_m;
            scan_lm->map().setAugmenter([this, point_std](const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
                core::TimedSection t(profiler_, "denseslam.3_template_augmentation");
                return denseGaussiansInBox(*partition_, *hybrid_, lo, hi, point_std);
            });
        }
        src->processScan(ekf_, scan);
        if (scan_lm) scan_lm->map().setAugmenter({});
        updates_ += src->mapChanges() - before;
    }
}

void DenseSlam::processBearingRange(const mrpt::obs::CObservationBearingRange& obs)
{
    for (const auto& src : point_sources_)
    {
        if (src->input() != PointSourceInput::BearingRange) continue;
        const PointObservations z = src->observe(obs);
        stats_.skipped_invalid += z.skipped_invalid;
        stats_.observations_with_id +=
            std::count_if(z.z.begin(), z.z.end(), [](const auto& o) { return o.id >= 0; });
        update(z.z, obs.sensorLocationOnRobot);
    }
}

void DenseSlam::processScan(const mrpt::obs::CObservation2DRangeScan& scan)
{
    std::vector<ekf::RangeBearingObs> z;
    std::vector<const std::string*> by;  // the source of each of z
    {
        core::TimedSection tle(profiler_, "denseslam.2_extract");
        // Every scan source's features, in registry order, each with its own noise.
        std::vector<std::pair<const std::string*, PointObservations>> found;
        for (const auto& src : point_sources_)
            if (src->input() == PointSourceInput::Scan)
            {
                const std::string& name = findPointSourceKind(src->name())->name;
                found.emplace_back(&name, src->observe(scan));
                stats_.point_features[name] += found.back().second.z.size();
            }
        // The sources classify the same beams: skipped readings counted once, as the last
        // source sees them.
        if (!found.empty()) stats_.skipped_invalid += found.back().second.skipped_invalid;
        dropSameObjects(found);
        for (const auto& [name, f] : found)
            for (const auto& o : f.z)
            {
                if (o.z(0) < options_.min_range || o.z(0) > options_.max_range) continue;
                z.push_back(o);
                by.push_back(name);
            }
        stats_.extracted += z.size();
    }
    const double t = scan.timestamp != INVALID_TIMESTAMP ? mrpt::Clock::toDouble(scan.timestamp)
                                                         : static_cast<double>(stats_.frames);
    recordFeatures(update(z, scan.sensorPose), by, t);
}

void DenseSlam::dropSameObjects(std::vector<std::pair<const std::string*, PointObservations>>& found)
{
    // One object, one observation: a feature that is the object of an earlier source's
    // feature of this scan goes (Options::same_object_distance).
    for (size_t k = 1; k < found.size(); ++k)
    {
        PointObservations& f = found[k].second;
        PointObservations kept;
        for (size_t i = 0; i < f.z.size(); ++i)
        {
            bool duplicate = false;
            for (size_t e = 0; e < k && !duplicate; ++e)
            {
                const PointObservations& g = found[e].second;
                for (size_t j = 0; j < g.z.size() && !duplicate; ++j)
                    duplicate = sameObject(f.z[i], f.beams[i], g.z[j], g.beams[j], options_.same_object_distance);
            }
            if (duplicate)
                ++stats_.point_duplicates[*found[k].first];
            else
            {
                kept.z.push_back(f.z[i]);
                kept.beams.push_back(f.beams[i]);
            }
        }
        f.z = std::move(kept.z);
        f.beams = std::move(kept.beams);
    }
}

void DenseSlam::recordFeatures(const ekf::UpdateReport& report,
                               const std::vector<const std::string*>& by, double t)
{
    for (size_t i = 0; i < report.assigned_ids.size() && i < by.size(); ++i)
    {
        const long id = report.assigned_ids[i];
        if (id < 0) continue;
        const auto [it, fresh] = features_.try_emplace(id);
        if (fresh)
        {
            it->second.created_by = *by[i];
            it->second.first_t = t;
        }
        it->second.last_t = t;
        ++it->second.observations[*by[i]];
    }
    // Tentative landmarks the filter pruned leave the bookkeeping with it.
    if (report.pruned > 0)
        for (auto it = features_.begin(); it != features_.end();)
            it = ekf_.hasLandmark(it->first) ? std::next(it) : features_.erase(it);
}

ekf::UpdateReport DenseSlam::update(const std::vector<ekf::RangeBearingObs>& obs,
                                    const mrpt::poses::CPose3D& sensor)
{
    if (obs.empty()) return {};
    core::TimedSection tle(profiler_, "denseslam.3_update");
    stats_.observations += obs.size();
    if (motion_)
    {
        // Sec. 6.3: observations in dynamic cells create no landmark; the report is
        // given back per observation of `obs` (-1 for those dropped).
        std::vector<size_t> kept;
        const auto passed = motion_->filterObservations(obs, ekf_, partition_.get(), sensor, kept);
        ekf::UpdateReport r = passed.empty() ? ekf::UpdateReport{} : ekf_.updateRangeBearing(passed, sensor);
        if (!passed.empty()) ++updates_;
        motion_->noteUpdate(r, frame_t_);
        std::vector<long> ids(obs.size(), -1);
        for (size_t i = 0; i < kept.size() && i < r.assigned_ids.size(); ++i) ids[kept[i]] = r.assigned_ids[i];
        r.assigned_ids = std::move(ids);
        stats_.add(r);
        return r;
    }
    const auto r = ekf_.updateRangeBearing(obs, sensor);
    ++updates_;
    stats_.add(r);
    return r;
}

}  // namespace hymm::denseslam
