/**
 * @file LandmarkSources.h
 * @brief Registered landmark sources that run a step of their own on every laser scan
 *        ([DenseSlam] landmark_source names them, alone or beside one of the point
 *        sources bearing_range, laser_trees, both, laser_reflectors,
 *        laser_reflectors_and_trees).
 *
 * Each kind declares its name, the ini sections it reads and a factory; the pipeline
 * builds the sources listed in landmark_source from the registry and calls their
 * per-scan step after the point sources of the same scan. Adding a source is one entry
 * in LandmarkSources.cpp and its class. Registered today:
 *  - scan_landmarks: Scan-SLAM pose landmarks with templates (thesis ch. 5,
 *    hymm::scanslam::ScanLandmarkMap).
 */
#pragma once

#include <hymm/ekf/EkfSlam.h>
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

/** One registered kind of source. */
struct LandmarkSourceKind
{
    std::string name;      //!< the landmark_source token
    std::string sections;  //!< ini sections it reads (documentation)
    std::function<std::unique_ptr<ScanLandmarkSource>(const mrpt::config::CConfigFileBase*)> make;
};

/** Every registered kind, in a fixed order. */
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
    std::vector<std::pair<std::string, size_t>> counters() const override { return map_->stats().list(); }
    void saveState(mrpt::serialization::CArchive& out) const override { map_->saveState(out); }
    void loadState(mrpt::serialization::CArchive& in) override { map_->loadState(in); }
    const scanslam::ScanLandmarkMap& map() const { return *map_; }

private:
    std::unique_ptr<scanslam::ScanLandmarkMap> map_;
};

}  // namespace hymm::denseslam
