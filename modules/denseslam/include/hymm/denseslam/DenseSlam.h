/**
 * @file DenseSlam.h
 * @brief The DenseSLAM pipeline: one rawlog entry at a time, the steps of thesis
 *        Fig. 3.3 — motion prediction, landmark extraction, data association and EKF
 *        update/augmentation — with the dense layers hanging off the feature map.
 *
 * The pipeline owns the feature EKF and the landmark extractors; it knows nothing about
 * files or command lines (SlamApp does that), so a robot program can feed it rawlog
 * entries or live observations directly.
 *
 * Dense mapping (optional, [DenseSlam] dense_layers / classic_grid): after the EKF
 * update of each sensory frame,
 *  4. regions: LTRs whose vertex landmarks left the map are removed (with their dense
 *     content), then RegionPartition::update() refreshes the current vertices and grows
 *     new regions around the vehicle (Sec. 3.5). update() scans every landmark id once,
 *     O(n) per call; it is called only in frames where the EKF state was updated (the
 *     landmark estimates changed), other frames leave the partition as it is;
 *  5. dense: every CObservation2DRangeScan of the frame is fused into the
 *     HybridMetricMap (and the ClassicOccupancyGrid baseline) at the vehicle pose
 *     estimate of observation time; the scan's own sensorPose places the sensor on the
 *     vehicle (ScanPoints::fromRangeScan): 5a stored returns into the regions now
 *     covering them, 5b the scan into the layers, 5c virtual landmarks for returns no
 *     region holds, 5d the rest into the delayed store;
 *  6. motion layers (below);
 *  7. the HLL search, when due (Sec. 6.1).
 * Information flows one way (Sec. 3.2, UIF): the dense part reads the filter through
 * EkfCovarianceView and never writes to it, so the feature map and the path are the
 * same, bit for bit, with or without dense layers.
 *
 * Motion layers (optional, [DynamicSlam] enabled, Sec. 6.3; needs the occupancy layer):
 * a dynamic::SlamMotionHook is called before each EKF update (observations in dynamic
 * cells create no landmark) and after step 5 (slow/fast differencing, flagging and
 * pruning of landmarks on moving objects). This is the one place where the dense part
 * acts on the feature map, by choice of the user: with the hook off nothing changes.
 */
#pragma once

#include <hymm/core/TimeLogger.h>
#include <hymm/dense/ClassicOccupancyGrid.h>
#include <hymm/dense/HybridMetricMap.h>
#include <hymm/dense/ScanPoints.h>
#include <hymm/io/RawlogReader.h>
#include <hymm/dynamic/SlamMotionHook.h>
#include <hymm/denseslam/DenseSlamOptions.h>
#include <hymm/denseslam/DenseSlamStats.h>
#include <hymm/denseslam/LandmarkSources.h>
#include <hymm/denseslam/OdometryModel.h>
#include <hymm/ekf/EkfSlam.h>
#include <hymm/hll/HighLevelLandmarks.h>
#include <hymm/ltr/RegionPartition.h>
#include <hymm/ltr/VirtualLandmarks.h>
#include <hymm/scanslam/ScanOdometry.h>
#include <hymm/uif/DelayedDenseStore.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/CPose2D.h>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

namespace mrpt::serialization
{
class CArchive;
}

namespace hymm::denseslam
{
class DenseSlam
{
public:
    using Options = DenseSlamOptions;
    using LaserOptions = ::hymm::denseslam::LaserOptions;
    using DenseOptions = ::hymm::denseslam::DenseOptions;
    using Stats = DenseSlamStats;
    using PathSample = ::hymm::denseslam::PathSample;
    using LandmarkFeatures = ::hymm::denseslam::LandmarkFeatures;
    using OutsideReturnCell = ::hymm::denseslam::OutsideReturnCell;

    /** Builds the pipeline from an .ini: sections [DenseSlam], [Laser], [EkfSlam], the
     *  DenseOptions sections and those of every registered point source (checked even
     *  when not in use) and of the per-scan sources named in landmark_source
     *  (LandmarkSources.h). */
    static DenseSlam fromConfig(const mrpt::config::CConfigFileBase& cfg);

    /** The landmark sources of opts.point_sources and opts.scan_sources read their
     *  sections of `sources_cfg` ([TreeExtractor], [ReflectorExtractor], [ScanLandmarks],
     *  ...; their defaults when null). */
    DenseSlam(const Options& opts, const ekf::EkfSlam::Options& ekf_opts,
              const DenseOptions& dense_opts = {},
              const mrpt::config::CConfigFileBase* sources_cfg = nullptr);

    /** Processes one rawlog entry (actions, sensory frame or single observation). */
    void processEntry(const io::RawlogEntry& entry);

    /** Applies an odometry increment (the action of an MRPT rawlog). With [ScanOdometry]
     *  enabled the increments are composed and applied by the next processFrame(), fused
     *  there with the alignment of its scan to the previous one (flushOdometry() applies
     *  what is pending at the end of a log). */
    void processOdometry(const mrpt::poses::CPosePDFGaussian& increment);
    /** Applies the odometry still pending ([ScanOdometry] enabled: the increments since
     *  the last frame) as it is; a no-op otherwise. */
    void flushOdometry();

    /** Processes the observations of one sensory frame and records a path sample.
     *  Observations with an unusable sensor pose or scan geometry are left out
     *  (Stats::observations_invalid_geometry). */
    void processFrame(const mrpt::obs::CSensoryFrame& frame);

    const ekf::EkfSlam& ekf() const { return ekf_; }
    const std::vector<PathSample>& path() const { return path_; }
    const Stats& stats() const { return stats_; }
    const Options& options() const { return options_; }
    mrpt::system::CTimeLogger& profiler() { return profiler_.get(); }
    /** The scan observations (of laser_reflectors, laser_trees) behind every landmark now
     *  in the filter; landmarks never observed in a scan are absent (all of them with
     *  bearing_range). */
    const std::map<long, LandmarkFeatures>& landmarkFeatures() const { return features_; }
    /** The point sources in use (Options::point_sources). */
    const std::vector<std::unique_ptr<PointLandmarkSource>>& pointSources() const { return point_sources_; }
    /** The registered per-scan landmark sources in use (Options::scan_sources). */
    const std::vector<std::unique_ptr<ScanLandmarkSource>>& scanSources() const { return sources_; }
    /** The wheels' turn bias state ([DenseSlam] turn_bias_state): estimate and std
     *  [rad/m]; nullopt without it. */
    std::optional<std::pair<double, double>> turnBias() const;
    /** Counters of the turn bias state's scan-odometry observations (keyframe copies,
     *  alignments fused, gated, failed numerically). */
    struct TurnBiasStats
    {
        size_t copies = 0, fused = 0, gated = 0, failed = 0;
    };
    const TurnBiasStats& turnBiasStats() const { return turn_bias_stats_; }
    /** Scan-matching odometry ([ScanOdometry]); nullptr unless enabled. */
    const scanslam::ScanOdometry* scanOdometry() const { return scan_odometry_.get(); }
    /** The scan_landmarks source, or nullptr when it is not in use. */
    const ScanLandmarksSource* scanLandmarks() const;
    /** Every registered source's counters as "<source>.<counter>", then the scan
     *  odometry's as "scan_odometry.<counter>" when it is on, and the turn bias state's
     *  scan-odometry counters as "turn_bias_state.<counter>". */
    std::vector<std::pair<std::string, size_t>> scanSourceCounters() const;

    /** Brings the current vertices of every region to the latest landmark estimates
     *  (RegionPartition::updateVertexPositions, O(regions)). With [LtrPartition]
     *  local_refresh the per-step refresh only reaches regions near the vehicle, so call
     *  this before rendering or saving the global dense map; without it, it is a no-op
     *  in effect (every region is already current after each update). */
    void refreshRegions();

    /** The LTRs; nullptr when no dense layer is on. */
    const ltr::RegionPartition* partition() const { return partition_.get(); }
    /** The dense layers; nullptr when no dense layer is on. */
    const dense::HybridMetricMap* hybridMap() const { return hybrid_.get(); }
    /** Passive-state ids of the virtual landmarks in use (Sec. 3.5.1); their estimates
     *  are ekf().passive().mean(id). */
    const std::set<long>& virtualLandmarkIds() const { return virtual_ids_; }
    /** The delayed-initialisation store (Sec. 3.7.3); nullptr unless enabled. */
    const uif::DelayedDenseStore* delayedStore() const { return store_.get(); }
    /** High-level landmarks (Sec. 6.1); nullptr unless [HighLevelLandmarks] enabled. */
    const hll::HighLevelLandmarks* highLevelLandmarks() const { return hll_.get(); }
    /** The motion layers and their use (Sec. 6.3); nullptr unless [DynamicSlam] enabled. */
    const dynamic::SlamMotionHook* motionHook() const { return motion_.get(); }
    /** The returns that fell in no region when seen, per cell (OutsideReturnCell): one
     *  entry per cell holding returns, ordered by cell. */
    std::vector<OutsideReturnCell> outsideReturnCells() const;
    /** The classic grid baseline; nullptr unless classic_grid is on. */
    const dense::ClassicOccupancyGrid* classicGrid() const { return classic_.get(); }

    /** Saved run state (hymm-slam --save-state / --resume): the filter, the dense part
     *  and every counter and piece of bookkeeping a later entry reads, bit for bit, so
     *  that a run continued from it gives the uninterrupted run's results. loadState()
     *  expects a pipeline built from the same config (hymm::app checks it) and throws
     *  std::runtime_error on a corrupt or truncated state. Source: DenseSlamState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

private:
    /** Class names and stamps of a frame's observations (duplicate detection). */
    using FrameSignature = std::vector<std::pair<const char*, mrpt::Clock::time_point>>;

    // processFrame's steps, in order.
    /** `input`, or its observations with a usable geometry copied into `filtered`
     *  (the others counted in Stats::observations_invalid_geometry). */
    const mrpt::obs::CSensoryFrame& usableObservations(const mrpt::obs::CSensoryFrame& input,
                                                       mrpt::obs::CSensoryFrame& filtered);
    static FrameSignature frameSignature(const mrpt::obs::CSensoryFrame& frame);
    /** [ScanOdometry]: the pending increment fused with the alignment of the frame's
     *  first scan to the previous scan, then the prediction (step 1). */
    void applyPendingOdometry(const mrpt::obs::CSensoryFrame& frame);
    /** EKF prediction with an increment (after the checks and noise of processOdometry);
     *  with the turn bias state, through it. */
    void predict(const scanslam::ScanOdometry::Increment& increment);
    /** Turn bias state with [ScanOdometry]: the last alignment fused as an observation of
     *  the vehicle from its copy at the reference scan; a new copy when the scan became
     *  the reference. */
    void observeFromReferenceCopy();
    /** The wheels' increment with the turn bias estimate removed (its uncertainty added):
     *  what the matcher is started from. */
    scanslam::ScanOdometry::Increment unbiasedByState(const scanslam::ScanOdometry::Increment& wheel) const;
    /** True if the frame repeats the previous one (same stamped observations, no
     *  prediction in between): skipped, its readings are not used twice. */
    bool repeatsPreviousFrame(const FrameSignature& signature) const;
    /** Steps 2-3 for each observation; returns the frame's time (NaN when unstamped). */
    double observeFrame(const mrpt::obs::CSensoryFrame& frame);
    void processObservation(const mrpt::obs::CObservation& o);
    /** A 2D scan: point sources, per-scan sources, HLL observations. */
    void processScanObservation(const mrpt::obs::CObservation2DRangeScan& scan);
    /** Time and odometry books of the frame, its path sample; returns the sample's time. */
    double endFrame(double t, FrameSignature signature);

    /** The bearing-range point sources' observations of `obs`, one update each. */
    void processBearingRange(const mrpt::obs::CObservationBearingRange& obs);
    /** The scan point sources' features of `scan` in one update (same-object rule). */
    void processScan(const mrpt::obs::CObservation2DRangeScan& scan);
    /** Drops the features of `found` (scan sources' features of one scan, in registry
     *  order) that are the object of an earlier source's feature (same_object_distance). */
    void dropSameObjects(std::vector<std::pair<const std::string*, PointObservations>>& found);
    /** Builds the registered sources of Options::point_sources and scan_sources from
     *  `cfg` (their sections; defaults when null). */
    void makeSources(const mrpt::config::CConfigFileBase* cfg);
    /** The registered sources' step for one scan (after the point sources). */
    void processScanSources(const mrpt::obs::CObservation2DRangeScan& scan);
    void processOdometryObservation(const mrpt::obs::CObservation& obs);
    /** EKF update with the observations of one sensor (an empty report when `obs` is
     *  empty). */
    ekf::UpdateReport update(const std::vector<ekf::RangeBearingObs>& obs,
                             const mrpt::poses::CPose3D& sensor);
    /** Bookkeeping of landmarkFeatures() after an update with observations of the point
     *  sources `by` (one name per observation). */
    void recordFeatures(const ekf::UpdateReport& report, const std::vector<const std::string*>& by,
                        double t);
    /** Step 5c: virtual landmarks for returns no region holds (Sec. 3.5.1). */
    void createVirtualLandmarks(const std::vector<Eigen::Vector2d>& unassigned, double t);
    /** One apex of `p` at `depth` as a passive state and its region; false (and the
     *  passive state gone) when the partition refuses the region. */
    bool addVirtualRegion(const ltr::VirtualLandmarkProposal& p, double depth, double t);
    /** 1-sigma error (largest axis) a return fused now into `region_id` would keep
     *  (Options::max_local_std_m). */
    double localFusionStd(const ltr::LandmarkCovarianceView& view, long region_id) const;
    /** Removes the passive blocks of virtual landmarks no region uses any more. */
    void dropUnusedVirtualLandmarks();
    /** Steps 4-5 of the class comment for one frame: updateRegions, then
     *  insertDenseScan for every scan with the fusion gate of fusionGate. */
    void processDense(const mrpt::obs::CSensoryFrame& frame, double t, bool map_changed);
    /** Step 4: regions on landmarks that left the map go, the others follow the
     *  estimates (near the vehicle with local_refresh), new ones grow around it. */
    void updateRegions(const ltr::LandmarkCovarianceView& view,
                       const mrpt::obs::CSensoryFrame& frame, double t);
    /** How far from the vehicle the frame's scan returns can reach [m]. */
    double scanReach(const mrpt::obs::CSensoryFrame& frame) const;
    /** Options::max_local_std_m as a region filter, memoised per region in `ready`
     *  (empty: every region accepts). */
    dense::HybridMetricMap::RegionFilter fusionGate(const ltr::LandmarkCovarianceView& view,
                                                    std::unordered_map<long, bool>& ready) const;
    /** Step 5 for one scan: delayed returns into the regions now covering them, the scan
     *  into the layers, what no region holds to virtual landmarks and the store, the
     *  classic grid. */
    void insertDenseScan(const mrpt::obs::CObservation2DRangeScan& scan,
                         const mrpt::math::TPose2D& vehicle,
                         const dense::HybridMetricMap::RegionFilter& accept, double t);
    /** Step 5a: stored returns into the regions that exist now (Sec. 3.7.3). */
    void fuseDelayed();
    /** Step 5d: returns no region holds and the fallback did not keep (counted as
     *  dropped) into the delayed store as passive states, as raw (range, bearing). */
    void storeUnassigned(const dense::ScanPoints& pts, const dense::HybridMetricMap::InsertStats& st,
                         double t);
    /** Step 6 (Sec. 6.3): motion layers by differencing the regions in view (fast) and
     *  the regions due (slow); landmarks on moving objects flagged, pruned once gone. */
    void updateMotionLayers(double t);
    /** Step 7 (Sec. 6.1): the HLL search near the vehicle when it is due. */
    void searchHighLevelLandmarks(double t);
    /** Parts of saveState() / loadState() (DenseSlamState.cpp). */
    void saveDenseState(mrpt::serialization::CArchive& out) const;
    void loadDenseState(mrpt::serialization::CArchive& in);
    void loadBookkeeping(mrpt::serialization::CArchive& in);
    /** The pending wheel increment, the scan odometry and the turn bias state's counters. */
    void saveOdometryState(mrpt::serialization::CArchive& out) const;
    void loadOdometryState(mrpt::serialization::CArchive& in);

    Options options_;
    ekf::EkfSlam ekf_;
    std::vector<PathSample> path_;
    struct OutsideSum
    {
        Eigen::Vector2d sum = Eigen::Vector2d::Zero();
        size_t returns = 0, kept = 0;
    };
    std::unordered_map<std::int64_t, OutsideSum> outside_;  //!< by cell (outsideReturnCells)
    Stats stats_;
    std::map<long, LandmarkFeatures> features_;
    std::optional<mrpt::poses::CPose2D> last_odometry_;  //!< for observation-only rawlogs
    size_t updates_ = 0;  //!< EKF updates applied so far
    std::unique_ptr<ltr::RegionPartition> partition_;
    std::unique_ptr<dense::HybridMetricMap> hybrid_;
    std::unique_ptr<dense::ClassicOccupancyGrid> classic_;
    std::unique_ptr<dynamic::SlamMotionHook> motion_;  //!< nullptr unless enabled
    std::unique_ptr<hll::HighLevelLandmarks> hll_;     //!< nullptr unless enabled
    std::unique_ptr<scanslam::ScanOdometry> scan_odometry_;  //!< nullptr unless enabled
    /** Reserved EKF ids (never a landmark's) of the turn bias and of the vehicle's copy at
     *  the scan odometry's reference scan. */
    static constexpr long kTurnBiasId = ekf::StateLayout::kFirstReservedId;
    static constexpr long kReferenceCopyId = kTurnBiasId + 1;
    TurnBiasStats turn_bias_stats_;
    /** [ScanOdometry]: the odometry since the last frame, not applied yet. */
    std::optional<scanslam::ScanOdometry::Increment> pending_odometry_;
    double frame_t_ = 0;  //!< [s] time of the frame being processed (motion hook)
    std::optional<double> last_stamp_;  //!< [s] stamp of the previous stamped frame
    /** The previous frame as duplicate detection sees it: its observations' class names
     *  and stamps, and the predictions made before it ended. */
    FrameSignature last_frame_signature_;
    size_t predictions_at_last_frame_ = 0;
    ltr::VirtualLandmarkOptions virtual_options_;
    std::unique_ptr<uif::DelayedDenseStore> store_;  //!< nullptr unless enabled
    std::set<long> virtual_ids_;  //!< passive blocks of ekf_ that are virtual landmarks
    /** Virtual landmarks live in the passive-state id space, far above real landmark ids. */
    long next_virtual_id_ = 1L << 40;
    core::LazyTimeLogger profiler_;  //!< made in the constructor, from Options::enable_profiler
    std::vector<std::unique_ptr<PointLandmarkSource>> point_sources_;  //!< registry order
    std::vector<std::unique_ptr<ScanLandmarkSource>> sources_;  //!< registered per-scan sources
};

}  // namespace hymm::denseslam
