/**
 * @file LandmarkSources.h
 * @brief Registered landmark sources: what turns the rawlog's observations into
 *        observations of landmarks for the feature EKF ([DenseSlam] landmark_source
 *        names the ones in use).
 *
 * Two families, each a registry of kinds (name, ini sections, factory); the pipeline
 * builds the sources landmark_source names and iterates over them. Adding a source is
 * one row in LandmarkSources.cpp and its class:
 *  - point sources (2-DOF point landmarks, Eq. 2.53 augmentation): bearing_range (a
 *    range-bearing sensor's CObservationBearingRange), laser_reflectors (beacons by
 *    intensity) and laser_trees (trunks) found in a CObservation2DRangeScan
 *    (PointSources.cpp). The scan sources of one scan are fused in one update, in
 *    registry order; a feature of a later source that is the object of an earlier
 *    source's feature of the same scan (beams overlap, or centres within [DenseSlam]
 *    same_object_distance_m) is dropped, so one object is one observation;
 *  - per-scan sources with a step of their own on every laser scan, run after the
 *    point sources of the same scan: scan_landmarks, Scan-SLAM pose landmarks (3-DOF)
 *    with templates (thesis ch. 5, hymm::scanslam::ScanLandmarkMap).
 */
#pragma once

#include <hymm/ekf/EkfSlam.h>
#include <mrpt/obs/CObservation.h>
#include <hymm/scanslam/ScanLandmarkMap.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace hymm::denseslam
{
/** What a point source reads. */
enum class PointSourceInput
{
    BearingRange,  //!< mrpt::obs::CObservationBearingRange
    Scan           //!< mrpt::obs::CObservation2DRangeScan
};

/** [DenseSlam] settings every point source applies. */
struct PointSourceSettings
{
    double min_range = 0.0;           //!< [m] observations closer than this are skipped
    double max_range = 1e9;           //!< [m] observations farther than this are skipped
    double sensor_std_range = 0.0;    //!< [m] > 0 overrides the source's own noise
    double sensor_std_bearing = 0.0;  //!< [rad] > 0 overrides the source's own noise
    bool use_landmark_ids = true;     //!< keep the ids the rawlog carries
    /** The observation noise (range, bearing) with the overrides applied. */
    Eigen::Matrix2d noise(double std_range, double std_bearing) const;
};

/** Observations of point landmarks one source found in one observation, in the
 *  sensor's frame (range, bearing). */
struct PointObservations
{
    std::vector<ekf::RangeBearingObs> z;
    /** Scan sources: the (first, last) beam behind each of z, for the same-object rule.
     *  Scan sources return every feature they found; the pipeline drops the duplicates
     *  and then those outside [min_range, max_range] (not counted as skipped). */
    std::vector<std::pair<size_t, size_t>> beams;
    size_t skipped_invalid = 0;  //!< readings the source skipped (NaN, out of range, ...)
};

/** A source of point-landmark observations. */
class PointLandmarkSource
{
public:
    virtual ~PointLandmarkSource() = default;
    virtual std::string name() const = 0;
    virtual PointSourceInput input() const = 0;
    /** The point landmarks in `obs`, an observation of input()'s class. */
    virtual PointObservations observe(const mrpt::obs::CObservation& obs) const = 0;
};

/** One registered kind of point source. */
struct PointSourceKind
{
    std::string name;      //!< the landmark_source token
    std::string sections;  //!< ini sections it reads (documentation)
    PointSourceInput input;
    /** A source reading its sections of `cfg` (defaults when null; a malformed key
     *  throws). */
    std::function<std::unique_ptr<PointLandmarkSource>(const mrpt::config::CConfigFileBase*,
                                                       const PointSourceSettings&)>
        make;
};

/** Every registered point source, in the order the scan sources of one scan are fused. */
const std::vector<PointSourceKind>& pointSourceKinds();
/** The point source called `name`, or nullptr. */
const PointSourceKind* findPointSourceKind(const std::string& name);
/** landmark_source names that stand for several point sources: both = bearing_range +
 *  laser_trees, laser_reflectors_and_trees = laser_reflectors + laser_trees. */
const std::vector<std::pair<std::string, std::vector<std::string>>>& pointSourceAliases();

/** A landmark source with a per-scan step on the feature filter. */
class ScanLandmarkSource
{
public:
    virtual ~ScanLandmarkSource() = default;
    virtual std::string name() const = 0;
    /** Observes, updates and augments `ekf` with one scan (its sensorPose on the vehicle). */
    virtual void processScan(ekf::EkfSlam& ekf, const mrpt::obs::CObservation2DRangeScan& scan) = 0;
    /** EKF updates and augmentations made so far (the map changed when this grows). */
    virtual size_t mapChanges() const = 0;
    /** What the source did and skipped, by reason: (counter, count). */
    virtual std::vector<std::pair<std::string, size_t>> counters() const = 0;
    /** The source's state bit for bit, for a saved run (hymm-slam --save-state / --resume). */
    virtual void saveState(mrpt::serialization::CArchive& out) const = 0;
    virtual void loadState(mrpt::serialization::CArchive& in) = 0;
};

/** One registered kind of per-scan source. */
struct LandmarkSourceKind
{
    std::string name;      //!< the landmark_source token
    std::string sections;  //!< ini sections it reads (documentation)
    std::function<std::unique_ptr<ScanLandmarkSource>(const mrpt::config::CConfigFileBase*)> make;
};

/** Every registered per-scan source, in a fixed order. */
const std::vector<LandmarkSourceKind>& landmarkSourceKinds();
/** The kind called `name`, or nullptr. */
const LandmarkSourceKind* findLandmarkSourceKind(const std::string& name);

/** scan_landmarks: Scan-SLAM pose landmarks (thesis ch. 5). */
class ScanLandmarksSource : public ScanLandmarkSource
{
public:
    explicit ScanLandmarksSource(std::unique_ptr<scanslam::ScanLandmarkMap> map) : map_(std::move(map)) {}
    std::string name() const override { return "scan_landmarks"; }
    void processScan(ekf::EkfSlam& ekf, const mrpt::obs::CObservation2DRangeScan& scan) override
    {
        map_->processScan(ekf, scan);
    }
    size_t mapChanges() const override { return map_->stats().updated + map_->stats().created; }
    /** The map's counters, and its revisits (kept as a list, RevisitLog). */
    std::vector<std::pair<std::string, size_t>> counters() const override
    {
        auto out = map_->stats().list();
        out.emplace_back("revisits", map_->revisits().size());
        return out;
    }
    void saveState(mrpt::serialization::CArchive& out) const override { map_->saveState(out); }
    void loadState(mrpt::serialization::CArchive& in) override { map_->loadState(in); }
    const scanslam::ScanLandmarkMap& map() const { return *map_; }
    scanslam::ScanLandmarkMap& map() { return *map_; }

private:
    std::unique_ptr<scanslam::ScanLandmarkMap> map_;
};

}  // namespace hymm::denseslam
