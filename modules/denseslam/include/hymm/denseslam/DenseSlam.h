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
 *     vehicle (ScanPoints::fromRangeScan).
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

#include <hymm/dense/ClassicOccupancyGrid.h>
#include <hymm/dense/HybridMetricMap.h>
#include <hymm/dense/ScanPoints.h>
#include <hymm/io/RawlogReader.h>
#include <hymm/dynamic/SlamMotionHook.h>
#include <hymm/denseslam/LandmarkSources.h>
#include <hymm/denseslam/OdometryModel.h>
#include <hymm/ekf/EkfSlam.h>
#include <hymm/hll/HighLevelLandmarks.h>
#include <hymm/ltr/RegionPartition.h>
#include <hymm/ltr/VirtualLandmarks.h>
#include <hymm/uif/DelayedDenseStore.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/system/CTimeLogger.h>

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

    struct Options : public mrpt::config::CLoadableOptions
    {
        /** [DenseSlam] landmark_source is a comma-separated list of registered sources
         *  (LandmarkSources.h), each at most once: point sources (bearing_range,
         *  laser_reflectors, laser_trees, or the aliases both and
         *  laser_reflectors_and_trees) and per-scan sources (scan_landmarks). */
        std::vector<std::string> point_sources{"bearing_range"};  //!< in registry order
        std::vector<std::string> scan_sources;  //!< per-scan sources, in list order
        bool use_landmark_ids = true;   //!< use IDs the rawlog carries; false: data association
        double odometry_cov_scale = 1.0;  //!< multiplies the odometry covariance of the rawlog
        double odometry_std_xy = 0.0;     //!< [m] added in quadrature to the odometry (per step)
        double odometry_std_phi = 0.0;    //!< [rad] likewise (ini: odometry_std_phi_deg)
        /** Covariance of the increments between CObservationOdometry readings
         *  (observation-format rawlogs carry none; OdometryModel.h). */
        OdometryModel odometry_model = OdometryModel::Thrun;
        ThrunOdometryParams thrun;  //!< odometry_model = thrun (ini: odometry_thrun_*)
        double sensor_std_range = 0.0;    //!< [m] > 0 overrides the rawlog's sensor noise
        double sensor_std_bearing = 0.0;  //!< [rad] > 0 overrides (ini: sensor_std_bearing_deg)
        double min_range = 0.0;           //!< [m] observations closer than this are skipped
        double max_range = 1e9;           //!< [m] observations farther than this are skipped
        /** [m] several scan point sources (laser_reflectors_and_trees): a feature whose
         *  beams overlap those of an earlier source's feature of the same scan (a tree on
         *  a reflector's beams), or whose centre lies within this distance of it, is the
         *  same object (a beacon on a pole or trunk) and is dropped; 0 = beam overlap
         *  only. (ini: same_object_distance_m) */
        double same_object_distance = 1.0;
        bool enable_profiler = false;
        /** Kinds of the HYMM's dense layers to keep (ini: dense_layers), names of
         *  dense::layerKinds() (points, occupancy, particles Sec. 4.2, sog Sec. 4.3,
         *  property), each at most once; empty = none. */
        std::vector<std::string> dense_layers;
        bool classic_grid = false;     //!< also build the classic occupancy-grid baseline
        double laser_std_range = 0.1;    //!< [m] laser range noise (delayed store covariances)
        double laser_std_bearing = 0.017453292519943295;  //!< [rad] (ini: laser_std_bearing_deg)
        /** [m] a scan is fused into a region only while the error its returns would keep
         *  in that region's local coordinates (1-sigma, largest axis, from the vehicle's
         *  uncertainty relative to the vertices: ltr::localFusionCovariance at the
         *  triangle's centroid) is at most this (Sec. 3.6, 3.7.3); 0 = always fuse. */
        double max_local_std_m = 0.0;
        /** [m] cell of the per-cell tally of the returns in no region
         *  (outsideReturnCells). */
        double outside_cell_m = 0.05;
        /** Regions also on the pose landmarks (scan landmarks, HLLs), a vertex at each
         *  one's frame origin: a dense map where there is no point landmark (thesis 6.2,
         *  DenseSLAM on scan landmarks). False: point landmarks only. */
        bool pose_landmark_vertices = false;

        /** True if a layer of the HYMM is on (regions are grown only then; the classic
         *  grid does not need them). */
        bool denseLayers() const { return !dense_layers.empty(); }
        /** True if `kind` is in dense_layers. */
        bool denseLayer(const std::string& kind) const;
        /** True if a point source in use reads observations of `input`. */
        bool readsPoints(PointSourceInput input) const;
        /** The settings the point sources apply. */
        PointSourceSettings pointSettings() const;

        /** Every ini key of [DenseSlam], declared once (loader, saver, README table). */
        core::OptionTable table();
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                              const std::string& section) const override;
    };

    /** Settings of the dense part; read from [LtrPartition], [HybridMetricMap],
     *  [OccupancyLayer], [PointsLayer] and [ClassicOccupancyGrid]. The layers switched on
     *  come from Options::dense_* (ini: [DenseSlam] dense_layers), which override
     *  HybridMetricMap::Options::enable_*. */
    /**
     * Ini section [Laser]: the laser scanner's raw-return noise, one place for every part
     * that models a return: the delayed store's covariances (Options::laser_std_*) and the
     * particle and SOG layers' sensor model (ParticlesLayer / SogLayer range_std_m,
     * bearing_std_deg, used when a scan carries no noise of its own). The extractors'
     * std_range / std_bearing_deg are the noise of an extracted feature (a trunk centre),
     * not of a return, and stay in their sections. fromConfig: a [Laser] key overrides the
     * four places; the old per-section keys are deprecated (a warning on stderr) and an
     * error when [Laser] sets the same quantity.
     */
    struct LaserOptions
    {
        double std_range_m = 0.1;      //!< [m]
        double std_bearing_deg = 1.0;  //!< [deg]
        core::OptionTable table();
    };

    struct DenseOptions
    {
        ltr::RegionPartition::Options partition;
        ltr::VirtualLandmarkOptions virtual_landmarks;  //!< [VirtualLandmarks] (Sec. 3.5.1)
        uif::DelayedDenseStore::Options delayed;        //!< [DelayedDenseStore] (Sec. 3.7.3)
        dense::HybridMetricMap::Options hybrid;
        dense::ClassicOccupancyGrid::Options classic;
        dynamic::SlamMotionHook::Options dynamic;  //!< [DynamicSlam], [MotionDetector] (Sec. 6.3)
        /** [HighLevelLandmarks] (Sec. 6.1; off by default; needs the occupancy and sog
         *  layers). Its matcher's section [HllMatcher] is read from the config given to
         *  the constructor. */
        hll::HighLevelLandmarks::Options hll;

        /** Reads the five sections, [DynamicSlam] and [MotionDetector] (absent sections keep the defaults; unknown keys are
         *  errors). */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg);
    };

    /** One estimated vehicle pose, after the update of a sensory frame. */
    struct PathSample
    {
        double t = 0;  //!< [s] timestamp of the frame's observations
        Eigen::Vector3d pose = Eigen::Vector3d::Zero();
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    };

    /** Counters of what the pipeline did and skipped, for summaries and metrics. */
    struct Stats
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
    };

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

    /** Applies an odometry increment (the action of an MRPT rawlog). */
    void processOdometry(const mrpt::poses::CPosePDFGaussian& increment);

    /** Processes the observations of one sensory frame and records a path sample.
     *  Observations with an unusable sensor pose or scan geometry are left out
     *  (Stats::observations_invalid_geometry). */
    void processFrame(const mrpt::obs::CSensoryFrame& frame);

    const ekf::EkfSlam& ekf() const { return ekf_; }
    const std::vector<PathSample>& path() const { return path_; }
    const Stats& stats() const { return stats_; }
    const Options& options() const { return options_; }
    mrpt::system::CTimeLogger& profiler() { return profiler_; }
    /** The scan observations (of laser_reflectors, laser_trees) behind every landmark now
     *  in the filter; landmarks never observed in a scan are absent (all of them with
     *  bearing_range). */
    const std::map<long, LandmarkFeatures>& landmarkFeatures() const { return features_; }
    /** The point sources in use (Options::point_sources). */
    const std::vector<std::unique_ptr<PointLandmarkSource>>& pointSources() const { return point_sources_; }
    /** The registered per-scan landmark sources in use (Options::scan_sources). */
    const std::vector<std::unique_ptr<ScanLandmarkSource>>& scanSources() const { return sources_; }
    /** The scan_landmarks source, or nullptr when it is not in use. */
    const ScanLandmarksSource* scanLandmarks() const;
    /** Every registered source's counters as "<source>.<counter>". */
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
    /** One entry per cell holding returns, ordered by cell. */
    std::vector<OutsideReturnCell> outsideReturnCells() const;
    /** The classic grid baseline; nullptr unless classic_grid is on. */
    const dense::ClassicOccupancyGrid* classicGrid() const { return classic_.get(); }

    /** Saved run state (hymm-slam --save-state / --resume): the filter, the dense part
     *  and every counter and piece of bookkeeping a later entry reads, bit for bit, so
     *  that a run continued from it gives the uninterrupted run's results. loadState()
     *  expects a pipeline built from the same config (hymm::app checks it). Both throw
     *  std::runtime_error when stateUnsupported() names a component, and loadState()
     *  on a corrupt or truncated state. Source: DenseSlamState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);
    /** The enabled component whose state the run state does not hold yet (empty: none). */
    std::string stateUnsupported() const;

private:
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
    /** Step 6: virtual landmarks for returns no region holds (Sec. 3.5.1). */
    void createVirtualLandmarks(const std::vector<Eigen::Vector2d>& unassigned, double t);
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
    /** Step 5b: returns no region holds and the fallback did not keep (counted as
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
    double frame_t_ = 0;  //!< [s] time of the frame being processed (motion hook)
    std::optional<double> last_stamp_;  //!< [s] stamp of the previous stamped frame
    /** The previous frame as duplicate detection sees it: its observations' class names
     *  and stamps, and the predictions made before it ended. */
    std::vector<std::pair<const char*, mrpt::Clock::time_point>> last_frame_signature_;
    size_t predictions_at_last_frame_ = 0;
    ltr::VirtualLandmarkOptions virtual_options_;
    std::unique_ptr<uif::DelayedDenseStore> store_;  //!< nullptr unless enabled
    std::set<long> virtual_ids_;  //!< passive blocks of ekf_ that are virtual landmarks
    /** Virtual landmarks live in the passive-state id space, far above real landmark ids. */
    long next_virtual_id_ = 1L << 40;
    mrpt::system::CTimeLogger profiler_{false, "hymm::DenseSlam"};
    std::vector<std::unique_ptr<PointLandmarkSource>> point_sources_;  //!< registry order
    std::vector<std::unique_ptr<ScanLandmarkSource>> sources_;  //!< registered per-scan sources
};

}  // namespace hymm::denseslam
