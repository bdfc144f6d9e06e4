/**
 * @file DenseSlamStats.h
 * @brief What the DenseSLAM pipeline (DenseSlam.h) reports besides its estimates: the
 *        path samples, the scan observations behind each landmark, the counters of what
 *        it did and skipped, and the tally of the returns no region held.
 */
#pragma once

#include <hymm/dense/HybridMetricMap.h>
#include <hymm/ekf/EkfSlam.h>
#include <hymm/uif/DelayedDenseStore.h>

#include <Eigen/Core>

#include <cstddef>
#include <map>
#include <string>

namespace hymm::denseslam
{
/** Per landmark: the scan point source whose observation created it (or first
 *  observed it), how many scan observations of each source the filter used for it
 *  (creation counts) and when. */
struct LandmarkFeatures
{
    std::string created_by;  //!< a point source's name (LandmarkSources.h)
    std::map<std::string, size_t> observations;  //!< by point source name
    double first_t = 0;  //!< [s] time of the first observation used (the scan's)
    double last_t = 0;   //!< [s] time of the latest observation used
    /** Observations of `source` used for this landmark. */
    size_t count(const std::string& source) const
    {
        const auto it = observations.find(source);
        return it == observations.end() ? 0 : it->second;
    }
};

/** One estimated vehicle pose, after the update of a sensory frame. */
struct PathSample
{
    double t = 0;  //!< [s] timestamp of the frame's observations
    Eigen::Vector3d pose = Eigen::Vector3d::Zero();
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
};

/** Counters of what the pipeline did and skipped, for summaries and metrics. */
struct DenseSlamStats
{
    size_t entries = 0, predictions = 0, frames = 0, observations = 0;
    size_t associated = 0, created = 0, rejected_gate = 0, ambiguous = 0,
           rejected_numeric = 0;
    /** NaN / non-finite / out-of-range readings (several scan point sources: the
     *  beams the last one skipped; they classify the same beams). */
    size_t skipped_invalid = 0;
    size_t scans = 0;
    size_t extracted = 0;             //!< observations of the scans given to the filter
    /** Features each scan point source found, by source name. */
    std::map<std::string, size_t> point_features;
    /** Of them, dropped as the object of an earlier source's feature of the same scan. */
    std::map<std::string, size_t> point_duplicates;
    size_t observations_with_id = 0;  //!< used with the landmark ID the rawlog carried
    // dense part
    size_t partition_updates = 0;   //!< calls of RegionPartition::update()
    size_t regions_created = 0, regions_removed = 0;
    size_t dense_scans = 0;         //!< scans fused into the dense layers
    size_t returns_stored = 0;      //!< returns assigned to a region
    size_t returns_outside = 0;     //!< returns in no region (not stored in a region)
    /** Of returns_outside: kept by the fallback ([HybridMetricMap]
     *  fallback_max_distance_m), stored in the delayed store (delayed_stored), or in no
     *  dense layer (returns_dropped): outside = fallback + delayed_stored + dropped. */
    size_t returns_fallback = 0;
    size_t returns_dropped = 0;
    /** Of returns_withheld: kept by the fallback in a nearby region that passes the
     *  max_local_std_m gate (the rest is dropped). */
    size_t returns_withheld_fallback = 0;
    size_t returns_withheld = 0;    //!< returns in a region not fused (max_local_std_m)
    size_t no_return_beams = 0;     //!< beams without return used as free space
    size_t failed_readings = 0;     //!< scan readings marked valid but NaN, inf or <= 0
    size_t virtual_landmarks = 0;   //!< virtual landmarks created with their region
    size_t virtual_rejected = 0;    //!< virtual apexes whose region failed a condition
    size_t delayed_stored = 0;      //!< returns kept by the delayed-initialisation store
    size_t delayed_fused = 0;       //!< stored returns later fused into a region
    /** Stored returns later kept by the dense fallback (in no region, a region within
     *  fallback_max_distance_m). */
    size_t delayed_fused_fallback = 0;
    /** Returns the store turned away or lost (uif::DelayedDenseStore::AddReport):
     *  in no potential region (require_potential_region), over the budget as a single
     *  scan, evicted (oldest first, budget or max_age_s), or whose passive block was
     *  gone. delayed_stored - delayed_fused - delayed_fused_fallback - evicted - lost are
     *  still waiting. */
    size_t delayed_outside_potential = 0;
    size_t delayed_thinned = 0;
    size_t delayed_evicted = 0;
    size_t delayed_lost = 0;
    // What the rawlog held and how much of it the run could use (hymm::app's run
    // warnings read these).
    size_t rawlog_observations = 0;  //!< non-null observations in frames and entries
    /** Of a class DenseSlam reads but the config does not use: bearing-range with
     *  laser landmarks only, 2D scans with bearing-range landmarks and no dense part. */
    size_t observations_unused = 0;
    /** Observations of classes DenseSlam does not read, by MRPT class name. */
    std::map<std::string, size_t> unsupported;
    size_t time_backwards = 0;  //!< frames stamped earlier than the previous stamped frame
    size_t time_repeated = 0;   //!< frames stamped the same as the previous stamped frame
    // Faults in well-formed rawlogs, each skipped or tolerated and counted.
    size_t odometry_invalid = 0;  //!< NaN / inf or over 1 km odometry increments, or NaN / inf readings, skipped
    /** Frames repeating the previous one (same stamp, same observation classes and
     *  stamps, no odometry in between): skipped, their information is not used twice. */
    size_t frames_duplicate = 0;
    size_t frames_without_odometry = 0;  //!< frames after the first with no prediction since the previous
    size_t scans_without_valid_beam = 0;  //!< laser scans with every beam marked invalid (or none)
    /** Observations whose sensor pose on the vehicle is NaN / inf or over 1 km from
     *  it, and 2D scans whose aperture is not in (0, 2 pi] or whose maximum range is
     *  not finite and positive: skipped whole (every reading would be placed at NaN or
     *  nowhere). */
    size_t observations_invalid_geometry = 0;

    // Each report of a step is merged here, in one place (DenseSlamStats.cpp).
    /** One EKF update: associated, created, rejected. */
    void add(const ekf::UpdateReport& r);
    /** One scan into the dense layers, with the readings ScanPoints skipped. */
    void add(const dense::HybridMetricMap::InsertStats& st, size_t failed_readings);
    /** Returns offered to the delayed store: those it did not store are dropped. */
    void add(const uif::DelayedDenseStore::AddReport& r);
    /** The store's returns fused into regions or the fallback, or lost. */
    void add(const uif::DelayedDenseStore::FuseReport& r);
};

/** The returns that fell in no region when seen, tallied as they arrive per square
 *  cell of Options::outside_cell_m (global position at the time): how many, how many
 *  of them the fallback kept, and their mean position, where the end-of-run
 *  diagnostic of why they fell outside (ltr/outside_causes.h) is evaluated. The
 *  causes are those of the FINAL map (a region may have formed there since), so they
 *  cannot be counted as the returns arrive; a tally per cell bounds the memory and
 *  the final classification by the area seen, not by the run's length. */
struct OutsideReturnCell
{
    Eigen::Vector2d p = Eigen::Vector2d::Zero();  //!< mean position of its returns
    size_t returns = 0;
    size_t kept = 0;  //!< of them, kept by the fallback
};

}  // namespace hymm::denseslam
