/**
 * @file SlamMotionHook.h
 * @brief The motion layers inside a SLAM pipeline (thesis Sec. 6.3): what a DenseSLAM
 *        owner calls at two points of each step, and what it does with the landmarks.
 *
 * Point 1, before the EKF update (filterObservations): an observation whose global
 * position (predicted vehicle pose, sensor mounting, range and bearing) falls in a
 * cell of a motion layer does not create a landmark (Sec. 6.3: observations of objects
 * that may move are kept out of the navigation map). Observations that would associate
 * with an existing landmark pass (a known id in the map, or, without ids, an existing
 * landmark within creation_guard_m), unless that landmark is flagged and
 * drop_flagged_observations is on.
 *
 * Point 2, after the dense fusion of the frame (afterFrame): the MotionDetector steps
 * with the regions in the sensor's view (box of view_range around the vehicle); then
 * landmarks in view that sit in a dynamic cell are flagged, and flagged landmarks not
 * observed for prune_unseen_s while in view (range and field of view) are removed
 * from the filter (a parked car that left: its
 * landmark is never observed again and would otherwise stay as a wrong anchor).
 *
 * The hook owns the detector and its bookkeeping and keeps no pointer to the pipeline,
 * so it can be moved onto another owner unchanged.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include "hymm/dynamic/MotionDetector.h"

#include <hymm/ekf/EkfSlam.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose3D.h>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace hymm::dynamic
{
class SlamMotionHook
{
public:
    /** Ini section [DynamicSlam] (the detector reads [MotionDetector]). */
    struct Options : public mrpt::config::CLoadableOptions
    {
        bool enabled = false;          //!< build the motion layers at all
        bool block_creation = true;    //!< no new landmarks from dynamic cells
        /** [m] without ids, an observation passes if a landmark is this close to it
         *  (it will associate, not create). */
        double creation_guard_m = 1.0;
        bool flag_landmarks = true;    //!< mark landmarks that sit in dynamic cells
        bool prune_flagged = true;     //!< remove flagged landmarks no longer observed
        /** Observations of a flagged landmark are dropped before the update (a known id,
         *  or, without ids, the nearest landmark within creation_guard_m is flagged): a
         *  landmark on a moving object stops correcting the vehicle, goes unobserved and
         *  is pruned. */
        bool drop_flagged_observations = false;
        double prune_unseen_s = 5.0;   //!< [s] unobserved this long before the removal
        double view_range_m = 25.0;    //!< [m] regions in a box of this half side are "in view"
        /** [deg] a flagged landmark within view_range_m and this field of view (about the
         *  vehicle's heading) that goes unobserved is gone; out of it, it is kept. */
        double view_fov_deg = 180.0;
        MotionDetector::Options detector;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        /** [section] and [MotionDetector]. */
        void loadAll(const mrpt::config::CConfigFileBase& cfg, const std::string& section = "DynamicSlam");
    };

    struct Stats
    {
        size_t creations_blocked = 0;   //!< observations dropped (would have created)
        size_t flagged_dropped = 0;     //!< observations of flagged landmarks dropped
        size_t landmarks_flagged = 0;   //!< distinct landmarks ever flagged
        size_t landmarks_pruned = 0;    //!< flagged landmarks removed
        size_t fast_differencings = 0;  //!< region differencings, fast layer
        size_t slow_differencings = 0;  //!< region differencings, slow layer
    };

    explicit SlamMotionHook(const Options& options);

    const Options& options() const { return options_; }
    const MotionDetector& detector() const { return detector_; }
    const Stats& stats() const { return stats_; }
    /** Landmarks flagged as sitting in a dynamic cell (and still in the map). */
    const std::set<long>& flagged() const { return flagged_; }

    /** Point 1. Returns the observations to give the filter; `kept[i]` is the index in
     *  `obs` of the i-th returned one. */
    std::vector<ekf::RangeBearingObs> filterObservations(
        const std::vector<ekf::RangeBearingObs>& obs, const ekf::EkfSlam& ekf,
        const ltr::RegionPartition* partition, const mrpt::poses::CPose3D& sensor,
        std::vector<size_t>& kept);
    /** Records which landmarks the update used (UpdateReport::assigned_ids) at time t. */
    void noteUpdate(const ekf::UpdateReport& report, double t);
    /** The partition removed these regions (with their dense content): their motion
     *  layers go too, in O(removed) (HybridMetricMap::removeRegions, same ids). */
    void removeRegions(const std::vector<long>& region_ids) { detector_.removeRegions(region_ids); }
    /** The detector's state, the counters and the flagged landmarks bit for bit, for a
     *  saved run (hymm-slam --save-state / --resume). */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

    /** Point 2. May remove landmarks from `ekf` (prune_flagged); returns their ids. */
    std::vector<long> afterFrame(const dense::HybridMetricMap& map, const ltr::RegionPartition& partition,
                                 ekf::EkfSlam& ekf, double t);

private:
    /** The 2-D landmark of `ids` nearest to `p` within `max_distance`, or -1. */
    long nearestLandmark(const ekf::EkfSlam& ekf, const std::vector<long>& ids, const Eigen::Vector2d& p,
                         double max_distance) const;
    /** Bounds (lo, hi) of where a landmark in view can sit in a dynamic cell: around the
     *  regions with a marked cell near the view box; none if there is no such region. */
    std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> markedBox(
        const ltr::RegionPartition& partition, const Eigen::Vector2d& vehicle) const;
    /** Flags the landmarks in the view box that sit in a dynamic cell (afterFrame). */
    void flagLandmarks(const ltr::RegionPartition& partition, const ekf::EkfSlam& ekf,
                       const Eigen::Vector2d& vehicle);

    Options options_;
    MotionDetector detector_;
    Stats stats_;
    std::set<long> flagged_;
    std::map<long, double> last_seen_;
};

}  // namespace hymm::dynamic
