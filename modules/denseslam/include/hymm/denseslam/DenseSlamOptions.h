/**
 * @file DenseSlamOptions.h
 * @brief The settings of the DenseSLAM pipeline (DenseSlam.h): [DenseSlam], [Laser] and
 *        the sections of the dense part. Each key is declared once in its section's
 *        core::OptionTable (loader, unknown-key check, saver, README table);
 *        DenseSlam::fromConfig reads them all.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <hymm/core/laser_noise.h>
#include <hymm/dense/ClassicOccupancyGrid.h>
#include <hymm/dense/HybridMetricMap.h>
#include <hymm/denseslam/LandmarkSources.h>
#include <hymm/denseslam/OdometryModel.h>
#include <hymm/dynamic/SlamMotionHook.h>
#include <hymm/hll/HighLevelLandmarks.h>
#include <hymm/ltr/RegionPartition.h>
#include <hymm/ltr/VirtualLandmarks.h>
#include <hymm/scanslam/ScanOdometry.h>
#include <hymm/uif/DelayedDenseStore.h>
#include <mrpt/config/CLoadableOptions.h>

#include <cmath>
#include <string>
#include <vector>

namespace hymm::denseslam
{
/** Ini section [DenseSlam]: the pipeline's own settings. */
struct DenseSlamOptions : public mrpt::config::CLoadableOptions
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
    /** The wheels' turn per metre travelled that they do not report (unequal wheel radii)
     *  as a state of the filter (EkfSlam::predictOdometryWithTurnBias): learnt from every
     *  observation through its correlation with the heading, and with [ScanOdometry] from
     *  each alignment to the keyframe, fused as an observation of the vehicle from a copy
     *  of its pose at the keyframe (README, "The wheels' turn bias as a state"). */
    bool turn_bias_state = false;
    double turn_bias_prior = 5 * M_PI / 180;  //!< its prior std [rad/m] (ini: turn_bias_prior_deg_per_m)
    /** Its random walk: std of its change per square root of a metre travelled
     *  [rad/m/sqrt(m)] (ini: turn_bias_walk_deg_per_m) */
    double turn_bias_walk = 0.01 * M_PI / 180;
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

/** Ini section [Laser]: the laser's raw-return noise (core/laser_noise.h). fromConfig: a
 *  [Laser] key overrides the delayed store's, the particle and SOG layers' (and the
 *  Scan-SLAM and HLL templates') noise; their own keys are deprecated. */
using LaserOptions = core::LaserNoise;

/** Settings of the dense part; read from [LtrPartition], [VirtualLandmarks],
 *  [DelayedDenseStore], [HybridMetricMap] with the sections of its layer kinds,
 *  [ClassicOccupancyGrid], [DynamicSlam], [MotionDetector] and [HighLevelLandmarks]
 *  (and [ScanOdometry], which is no dense setting but is read with them). The
 *  layers switched on come from DenseSlamOptions::dense_layers (ini: [DenseSlam]
 *  dense_layers), which override HybridMetricMap::Options::enable_*. */
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
    /** [ScanOdometry] (off by default): consecutive scans aligned and fused with the
     *  wheel odometry. Its matcher's section [ScanOdometryMatcher] is read from the config
     *  given to the constructor. */
    scanslam::ScanOdometry::Options scan_odometry;

    /** Reads the five sections, [DynamicSlam] and [MotionDetector] (absent sections keep the defaults; unknown keys are
     *  errors). */
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg);
};

}  // namespace hymm::denseslam
