/**
 * @file DenseSlam.cpp
 * @brief The pipeline's construction and its per-entry steps (DenseSlam.h): odometry
 *        (step 1), then per frame: usable observations, duplicate check, each
 *        observation to its landmark sources (steps 2-3; the sources and the update in
 *        DenseSlamLandmarks.cpp), path sample, then the dense part (steps 4-6) and the
 *        HLL search (step 7), both in DenseSlamDense.cpp.
 */
#include "hymm/denseslam/DenseSlam.h"
#include "usable_covariance.h"

#include <hymm/dense/LayerRegistry.h>
#include <hymm/core/TimeLogger.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/system/datetime.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace hymm::denseslam
{
DenseSlam::DenseSlam(const Options& opts, const ekf::EkfSlam::Options& ekf_opts,
                     const DenseOptions& dense_opts,
                     const mrpt::config::CConfigFileBase* sources_cfg)
    : options_(opts),
      ekf_(ekf_opts),
      virtual_options_(dense_opts.virtual_landmarks),
      profiler_(opts.enable_profiler, "hymm::DenseSlam")
{
    if (options_.denseLayers() && dense_opts.delayed.enabled)
        store_ = std::make_unique<uif::DelayedDenseStore>(dense_opts.delayed);
    if (options_.denseLayers())
    {
        partition_ = std::make_unique<ltr::RegionPartition>(dense_opts.partition);
        auto h = dense_opts.hybrid;
        for (const auto& name : options_.dense_layers)
            if (!dense::findLayerKind(name))
                throw std::invalid_argument("[DenseSlam] dense_layers: unknown layer kind '" + name +
                                            "' (known: " + dense::layerKindNames() + ")");
        for (const auto& kind : dense::layerKinds()) h.*(kind.enabled) = options_.denseLayer(kind.name);
        hybrid_ = std::make_unique<dense::HybridMetricMap>(h);
    }
    if (options_.classic_grid)
        classic_ = std::make_unique<dense::ClassicOccupancyGrid>(dense_opts.classic,
                                                                 dense_opts.hybrid.occupancy);
    if (dense_opts.dynamic.enabled)
    {
        if (!options_.denseLayer(dense::OccupancyLayer::kKind))
            throw std::invalid_argument(
                "[DynamicSlam] enabled = true needs the occupancy layer ([DenseSlam] dense_layers)");
        motion_ = std::make_unique<dynamic::SlamMotionHook>(dense_opts.dynamic);
    }
    if (dense_opts.hll.enabled)
    {
        if (!options_.denseLayer(dense::OccupancyLayer::kKind) || !options_.denseLayer(dense::SogLayer::kKind))
            throw std::invalid_argument(
                "[HighLevelLandmarks] enabled = true needs the occupancy and sog layers "
                "([DenseSlam] dense_layers)");
        hll_ = hll::HighLevelLandmarks::make(dense_opts.hll, sources_cfg);
    }
    if (dense_opts.scan_odometry.enabled)
        scan_odometry_ = scanslam::ScanOdometry::make(dense_opts.scan_odometry, sources_cfg);
    if (options_.turn_bias_state)
    {
        if (ekf_opts.jacobians == ekf::LinearisationPoint::Invariant)
            throw std::invalid_argument(
                "[DenseSlam] turn_bias_state = true needs [EkfSlam] jacobians = current or first_estimates");
        if (scan_odometry_ && dense_opts.scan_odometry.wheel_turn_bias)
            throw std::invalid_argument(
                "[DenseSlam] turn_bias_state and [ScanOdometry] wheel_turn_bias estimate the same bias: set one");
        ekf_.addAuxiliaryBlock(
            Eigen::VectorXd::Zero(1), Eigen::MatrixXd::Constant(1, 1, options_.turn_bias_prior * options_.turn_bias_prior),
            kTurnBiasId);
    }
    makeSources(sources_cfg);
}

void DenseSlam::makeSources(const mrpt::config::CConfigFileBase* cfg)
{
    for (const auto& name : options_.point_sources)
        if (!findPointSourceKind(name)) throw std::invalid_argument("unknown landmark source '" + name + "'");
    point_sources_.clear();
    for (const auto& kind : pointSourceKinds())
        if (std::find(options_.point_sources.begin(), options_.point_sources.end(), kind.name) !=
            options_.point_sources.end())
            point_sources_.push_back(kind.make(cfg, options_.pointSettings()));
    sources_.clear();
    for (const auto& name : options_.scan_sources)
    {
        const LandmarkSourceKind* kind = findLandmarkSourceKind(name);
        if (!kind) throw std::invalid_argument("unknown landmark source '" + name + "'");
        sources_.push_back(kind->make(cfg));
    }
}

void DenseSlam::processEntry(const io::RawlogEntry& entry)
{
    ++stats_.entries;
    if (entry.actions)
    {
        // Step 1 (Fig. 3.3): motion prediction from the odometry of the action.
        if (auto mov = entry.actions->getBestMovementEstimation())
        {
            mrpt::poses::CPosePDFGaussian inc;
            inc.copyFrom(*mov->poseChange);
            processOdometry(inc);
        }
    }
    if (entry.frame) processFrame(*entry.frame);
    if (entry.observation)
    {
        if (IS_CLASS(*entry.observation, mrpt::obs::CObservationOdometry))
        {
            ++stats_.rawlog_observations;
            processOdometryObservation(*entry.observation);
        }
        else
        {
            mrpt::obs::CSensoryFrame sf;
            sf.insert(entry.observation);
            processFrame(sf);
        }
    }
}

namespace
{
/** An observation whose geometry the pipeline can use: a sensor pose that is finite and
 *  within 1 km of the vehicle (a mount further out is a corrupt reading, and would place
 *  its returns where no grid index can represent them); for a 2D scan also a finite
 *  aperture in (0, 2 pi] and a finite positive maximum range (else every beam's bearing
 *  or its no-return length is NaN). */
bool usableGeometry(const mrpt::obs::CObservation& o)
{
    if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&o))
        if (!std::isfinite(scan->aperture) || scan->aperture <= 0 || scan->aperture > 2 * M_PI + 1e-6 ||
            !std::isfinite(scan->maxRange) || scan->maxRange <= 0)
            return false;
    constexpr double kMaxMount = 1000.0;  // [m]
    mrpt::poses::CPose3D p;
    o.getSensorPose(p);
    const double v[6] = {p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll()};
    return std::all_of(std::begin(v), std::end(v), [](double a) { return std::isfinite(a); }) &&
           std::abs(p.x()) <= kMaxMount && std::abs(p.y()) <= kMaxMount && std::abs(p.z()) <= kMaxMount;
}
}  // namespace

void DenseSlam::processFrame(const mrpt::obs::CSensoryFrame& input)
{
    mrpt::obs::CSensoryFrame filtered;
    const mrpt::obs::CSensoryFrame& frame = usableObservations(input, filtered);
    const size_t updates_before = updates_;
    FrameSignature signature = frameSignature(frame);
    if (repeatsPreviousFrame(signature))
    {
        ++stats_.frames_duplicate;
        return;
    }
    applyPendingOdometry(frame);
    const double t = endFrame(observeFrame(frame), std::move(signature));
    if (partition_ || classic_) processDense(frame, t, updates_ != updates_before);
    if (hll_) searchHighLevelLandmarks(t);
}

const mrpt::obs::CSensoryFrame& DenseSlam::usableObservations(const mrpt::obs::CSensoryFrame& input,
                                                              mrpt::obs::CSensoryFrame& filtered)
{
    // Observations with an unusable sensor pose or scan geometry leave the frame before
    // anything reads it (the filter, the scan sources, the dense part): counted, and seen
    // in the rawlog.
    const bool any_bad = std::any_of(input.begin(), input.end(),
                                     [](const auto& o) { return o && !usableGeometry(*o); });
    if (!any_bad) return input;
    for (const auto& o : input)
    {
        if (o && !usableGeometry(*o))
        {
            ++stats_.observations_invalid_geometry;
            ++stats_.rawlog_observations;
        }
        else
            filtered.insert(o);
    }
    return filtered;
}

DenseSlam::FrameSignature DenseSlam::frameSignature(const mrpt::obs::CSensoryFrame& frame)
{
    FrameSignature signature;
    for (const auto& o : frame)
        if (o) signature.emplace_back(o->GetRuntimeClass()->className, o->timestamp);
    return signature;
}

bool DenseSlam::repeatsPreviousFrame(const FrameSignature& signature) const
{
    // A frame repeating the previous one (a duplicated rawlog entry) would use the same
    // readings twice and make the filter overconfident.
    const bool stamped = !signature.empty() &&
                         std::all_of(signature.begin(), signature.end(), [](const auto& p)
                                     { return p.second != INVALID_TIMESTAMP; });
    return stamped && stats_.frames > 0 && stats_.predictions == predictions_at_last_frame_ &&
           signature.size() == last_frame_signature_.size() &&
           std::equal(signature.begin(), signature.end(), last_frame_signature_.begin(),
                      [](const auto& a, const auto& b)
                      { return std::strcmp(a.first, b.first) == 0 && a.second == b.second; });
}

double DenseSlam::observeFrame(const mrpt::obs::CSensoryFrame& frame)
{
    // Steps 2-3 (Fig. 3.3) for each observation; the frame's time is its first stamp.
    double t = std::nan("");
    for (const auto& o : frame)
    {
        if (!o) continue;
        if (std::isnan(t) && o->timestamp != INVALID_TIMESTAMP) t = mrpt::Clock::toDouble(o->timestamp);
        if (!std::isnan(t)) frame_t_ = t;
        ++stats_.rawlog_observations;
        processObservation(*o);
    }
    return t;
}

void DenseSlam::processObservation(const mrpt::obs::CObservation& o)
{
    if (const auto* br = dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&o))
    {
        if (options_.readsPoints(PointSourceInput::BearingRange))
            processBearingRange(*br);
        else
            ++stats_.observations_unused;
    }
    else if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&o))
        processScanObservation(*scan);
    else if (IS_CLASS(o, mrpt::obs::CObservationOdometry))
    {
        if (!scan_odometry_) processOdometryObservation(o);  // else applyPendingOdometry read it
    }
    else
        ++stats_.unsupported[o.GetRuntimeClass()->className];
}

void DenseSlam::processScanObservation(const mrpt::obs::CObservation2DRangeScan& scan)
{
    ++stats_.scans;
    bool any_valid = false;
    for (size_t i = 0; i < scan.getScanSize() && !any_valid; ++i) any_valid = scan.getScanRangeValidity(i);
    if (!any_valid) ++stats_.scans_without_valid_beam;
    const bool laser_points = options_.readsPoints(PointSourceInput::Scan);
    if (laser_points) processScan(scan);
    processScanSources(scan);
    if (hll_)
    {
        // The HLLs are observed like scan landmarks (Sec. 6.1.3): after the point
        // sources, before the dense part reads the filter.
        core::TimedSection tle(profiler_, "denseslam.3_hll_observe");
        const size_t before = hll_->mapChanges();
        hll_->processScan(ekf_, scan, frame_t_);
        updates_ += hll_->mapChanges() - before;
    }
    if (!laser_points && sources_.empty() && !partition_ && !classic_) ++stats_.observations_unused;
}

double DenseSlam::endFrame(double t, FrameSignature signature)
{
    if (!std::isnan(t))
    {
        if (last_stamp_ && t < *last_stamp_) ++stats_.time_backwards;
        if (last_stamp_ && t == *last_stamp_) ++stats_.time_repeated;
        last_stamp_ = t;
    }
    // Odometry may also come inside the frame (a CObservationOdometry): counted after it.
    if (stats_.frames > 0 && stats_.predictions == predictions_at_last_frame_) ++stats_.frames_without_odometry;
    last_frame_signature_ = std::move(signature);
    predictions_at_last_frame_ = stats_.predictions;
    ++stats_.frames;
    PathSample s;
    s.t = std::isnan(t) ? static_cast<double>(stats_.frames) : t;
    s.pose = ekf_.vehiclePose();
    s.cov = ekf_.vehicleCov();
    path_.push_back(s);
    return s.t;
}

}  // namespace hymm::denseslam
