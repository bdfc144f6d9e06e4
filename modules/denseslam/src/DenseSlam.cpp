#include "hymm/denseslam/DenseSlam.h"
#include "hymm/denseslam/VirtualLandmarkView.h"
#include "usable_covariance.h"

#include <cstring>
#include <hymm/uif/DelayedDenseStore.h>

#include <hymm/core/config_utils.h>
#include <hymm/dense/LayerRegistry.h>
#include <hymm/dense/ScanPoints.h>
#include <hymm/dense/geometry.h>
#include <hymm/denseslam/EkfCovarianceView.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/system/datetime.h>

#include <hymm/ltr/position_error.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <unordered_map>

namespace hymm::denseslam
{
namespace
{
/** What one EKF update did, added to the run's counters. */
void addUpdateCounts(DenseSlam::Stats& s, const ekf::UpdateReport& r)
{
    s.associated += r.associated;
    s.created += r.created;
    s.rejected_gate += r.rejected_gate;
    s.ambiguous += r.ambiguous;
    s.rejected_numeric += r.rejected_numeric;
}

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

DenseSlam::DenseSlam(const Options& opts, const ekf::EkfSlam::Options& ekf_opts,
                     const DenseOptions& dense_opts,
                     const mrpt::config::CConfigFileBase* sources_cfg)
    : options_(opts), ekf_(ekf_opts), virtual_options_(dense_opts.virtual_landmarks)
{
    if (options_.denseLayers() && dense_opts.delayed.enabled)
        store_ = std::make_unique<uif::DelayedDenseStore>(dense_opts.delayed);
    profiler_.enable(options_.enable_profiler);
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
    return out;
}

void DenseSlam::processScanSources(const mrpt::obs::CObservation2DRangeScan& scan)
{
    if (sources_.empty()) return;
    mrpt::system::CTimeLoggerEntry tle(profiler_, "denseslam.3_scan_sources");
    for (auto& src : sources_)
    {
        const size_t before = src->mapChanges();
        src->processScan(ekf_, scan);
        updates_ += src->mapChanges() - before;
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

void DenseSlam::processOdometry(const mrpt::poses::CPosePDFGaussian& increment)
{
    // A NaN / inf increment (or covariance) would poison the whole state, and a finite but
    // absurd one (a corrupt reading: no vehicle moves 1 km between two odometry readings)
    // would put the pose where no grid index can represent it: both skipped.
    // The same for a covariance that is no covariance (a negative variance, not symmetric)
    // or claims more than 1 km / a full turn of spread: it would make the filter's
    // covariance indefinite or overflow it.
    constexpr double kMaxStep = 1000.0;  // [m]
    if (!std::isfinite(increment.mean.x()) || !std::isfinite(increment.mean.y()) ||
        !std::isfinite(increment.mean.phi()) || !increment.cov.asEigen().allFinite() ||
        std::hypot(increment.mean.x(), increment.mean.y()) > kMaxStep ||
        !usableCovariance<3>(increment.cov.asEigen(), Eigen::Vector3d(kMaxStep, kMaxStep, 2 * M_PI)))
    {
        ++stats_.odometry_invalid;
        return;
    }
    mrpt::system::CTimeLoggerEntry tle(profiler_, "denseslam.1_predict");
    mrpt::poses::CPosePDFGaussian inc = increment;
    inc.cov *= options_.odometry_cov_scale;
    inc.cov(0, 0) += options_.odometry_std_xy * options_.odometry_std_xy;
    inc.cov(1, 1) += options_.odometry_std_xy * options_.odometry_std_xy;
    inc.cov(2, 2) += options_.odometry_std_phi * options_.odometry_std_phi;
    ekf_.predictOdometry(inc);
    ++stats_.predictions;
}

void DenseSlam::processOdometryObservation(const mrpt::obs::CObservation& obs)
{
    const auto& odo = dynamic_cast<const mrpt::obs::CObservationOdometry&>(obs);
    if (!std::isfinite(odo.odometry.x()) || !std::isfinite(odo.odometry.y()) ||
        !std::isfinite(odo.odometry.phi()))
    {
        ++stats_.odometry_invalid;  // the next good reading continues from the last good one
        return;
    }
    if (last_odometry_)
    {
        // The reading carries no covariance: the increment gets the motion model's.
        processOdometry(odometryIncrementPdf(odo.odometry - *last_odometry_,
                                             options_.odometry_model, options_.thrun));
    }
    last_odometry_ = odo.odometry;
}

void DenseSlam::processFrame(const mrpt::obs::CSensoryFrame& input)
{
    // Observations with an unusable sensor pose or scan geometry leave the frame before
    // anything reads it (the filter, the scan sources, the dense part): counted, and seen
    // in the rawlog.
    mrpt::obs::CSensoryFrame filtered;
    const bool any_bad = std::any_of(input.begin(), input.end(),
                                     [](const auto& o) { return o && !usableGeometry(*o); });
    if (any_bad)
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
    const mrpt::obs::CSensoryFrame& frame = any_bad ? filtered : input;
    const size_t updates_before = updates_;
    // A frame repeating the previous one (a duplicated rawlog entry) would use the same
    // readings twice and make the filter overconfident: skipped and counted.
    std::vector<std::pair<const char*, mrpt::Clock::time_point>> signature;
    for (const auto& o : frame)
        if (o) signature.emplace_back(o->GetRuntimeClass()->className, o->timestamp);
    const bool stamped = !signature.empty() &&
                         std::all_of(signature.begin(), signature.end(), [](const auto& p)
                                     { return p.second != INVALID_TIMESTAMP; });
    if (stamped && stats_.frames > 0 && stats_.predictions == predictions_at_last_frame_ &&
        signature.size() == last_frame_signature_.size() &&
        std::equal(signature.begin(), signature.end(), last_frame_signature_.begin(),
                   [](const auto& a, const auto& b)
                   { return std::strcmp(a.first, b.first) == 0 && a.second == b.second; }))
    {
        ++stats_.frames_duplicate;
        return;
    }
    double t = std::nan("");
    for (const auto& o : frame)
    {
        if (!o) continue;
        if (std::isnan(t) && o->timestamp != INVALID_TIMESTAMP)
            t = mrpt::Clock::toDouble(o->timestamp);
        if (!std::isnan(t)) frame_t_ = t;
        ++stats_.rawlog_observations;
        if (auto br = std::dynamic_pointer_cast<mrpt::obs::CObservationBearingRange>(o))
        {
            if (options_.readsPoints(PointSourceInput::BearingRange))
                processBearingRange(*br);
            else
                ++stats_.observations_unused;
        }
        else if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o))
        {
            ++stats_.scans;
            bool any_valid = false;
            for (size_t i = 0; i < scan->getScanSize() && !any_valid; ++i)
                any_valid = scan->getScanRangeValidity(i);
            if (!any_valid) ++stats_.scans_without_valid_beam;
            const bool laser_points = options_.readsPoints(PointSourceInput::Scan);
            if (laser_points) processScan(*scan);
            processScanSources(*scan);
            if (hll_)
            {
                // The HLLs are observed like scan landmarks (Sec. 6.1.3): after the
                // point sources, before the dense part reads the filter.
                mrpt::system::CTimeLoggerEntry tle(profiler_, "denseslam.3_hll_observe");
                const size_t before = hll_->mapChanges();
                hll_->processScan(ekf_, *scan, frame_t_);
                updates_ += hll_->mapChanges() - before;
            }
            if (!laser_points && sources_.empty() && !partition_ && !classic_)
                ++stats_.observations_unused;
        }
        else if (IS_CLASS(*o, mrpt::obs::CObservationOdometry))
        {
            processOdometryObservation(*o);
        }
        else
            ++stats_.unsupported[o->GetRuntimeClass()->className];
    }
    if (!std::isnan(t))
    {
        if (last_stamp_ && t < *last_stamp_) ++stats_.time_backwards;
        if (last_stamp_ && t == *last_stamp_) ++stats_.time_repeated;
        last_stamp_ = t;
    }
    // Odometry may also come inside the frame (a CObservationOdometry): counted after it.
    if (stats_.frames > 0 && stats_.predictions == predictions_at_last_frame_)
        ++stats_.frames_without_odometry;
    last_frame_signature_ = std::move(signature);
    predictions_at_last_frame_ = stats_.predictions;
    ++stats_.frames;
    PathSample s;
    s.t = std::isnan(t) ? static_cast<double>(stats_.frames) : t;
    s.pose = ekf_.vehiclePose();
    s.cov = ekf_.vehicleCov();
    path_.push_back(s);
    if (partition_ || classic_) processDense(frame, s.t, updates_ != updates_before);
    if (hll_) searchHighLevelLandmarks(s.t);
}

void DenseSlam::searchHighLevelLandmarks(double t)
{
    if (!hll_->due(t)) return;
    mrpt::system::CTimeLoggerEntry tle(profiler_, "denseslam.7_hll_search");
    // Areas of the Scan-SLAM templates in the filter: an HLL must not duplicate them.
    std::vector<hll::OrientedRect> exclusions;
    if (const auto* src = scanLandmarks())
        for (const auto& [id, tpl] : src->map().templates())
            if (ekf_.hasLandmark(id) && tpl.sog.size() > 0)
                exclusions.push_back(
                    hll::boundingRect(tpl.sog.points).placed(ekf_.landmarkBlockMean(id).head<3>()));
    hll_->search(t, ekf_, *partition_, *hybrid_, exclusions);
}

double DenseSlam::localFusionStd(const ltr::LandmarkCovarianceView& view, long region_id) const
{
    const auto& r = partition_->region(region_id);
    // Evaluated at the centroid, brought within the dense range of the vehicle: the
    // heading part of the error grows with the distance of the return.
    const Eigen::Vector2d vxy = view.vehiclePose().head<2>();
    Eigen::Vector2d x = (r.current[0] + r.current[1] + r.current[2]) / 3.0;
    const double d = (x - vxy).norm(), reach = hybrid_->options().max_range_m;
    if (d > reach) x = vxy + (x - vxy) * (reach / d);
    try
    {
        const Eigen::Matrix2d p = ltr::localFusionCovariance(view, r.vertex_ids, x);
        return std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(p).eigenvalues()(1)));
    }
    catch (const std::invalid_argument&)
    {
        return std::numeric_limits<double>::infinity();  // folded triangle: no frame to fuse into
    }
}

void DenseSlam::refreshRegions()
{
    if (!partition_) return;
    partition_->updateVertexPositions(VirtualLandmarkView(ekf_, virtual_ids_, options_.pose_landmark_vertices));
}

double DenseSlam::scanReach(const mrpt::obs::CSensoryFrame& frame) const
{
    double reach = hybrid_->options().max_range_m;  // scan returns are looked up this far
    for (const auto& o : frame)
        if (const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o))
            reach = std::max(reach, hybrid_->options().max_range_m +
                                        std::hypot(scan->sensorPose.x(), scan->sensorPose.y()));
    return reach;
}

void DenseSlam::updateRegions(const ltr::LandmarkCovarianceView& view,
                              const mrpt::obs::CSensoryFrame& frame, double t)
{
    mrpt::system::CTimeLoggerEntry tle(profiler_, "denseslam.4_regions");
    // local_refresh: only the regions the scans and the growth can reach follow the
    // new estimates (O(area) per step); a large vehicle correction (a loop closure)
    // refreshes every region. Otherwise every region and landmark, every step.
    const auto& po = partition_->options();
    const Eigen::Vector2d vehicle_xy = ekf_.vehiclePose().head<2>();
    const bool local = po.local_refresh && (vehicle_xy - ekf_.predictedPose().head<2>()).norm() <=
                                               po.full_refresh_correction_m;
    const double reach = scanReach(frame);
    // Regions anchored on landmarks that left the map go, with their dense content.
    const auto stale = local ? partition_->regionsWithMissingLandmarksNear(view, vehicle_xy, reach)
                             : partition_->regionsWithMissingLandmarks(view);
    for (long id : stale) partition_->removeRegion(id);
    if (!stale.empty())
    {
        stats_.regions_removed += stale.size();
        // Only the removed ids: walking the whole map here would make every step's cost
        // grow with the map.
        hybrid_->removeRegions(stale);
        if (motion_) motion_->removeRegions(stale);
        dropUnusedVirtualLandmarks();
    }
    // Refreshes the current vertices (near the vehicle or all), then grows around it.
    stats_.regions_created +=
        (local ? partition_->updateNear(view, t, reach) : partition_->update(view, t)).size();
    ++stats_.partition_updates;
}

dense::HybridMetricMap::RegionFilter DenseSlam::fusionGate(const ltr::LandmarkCovarianceView& view,
                                                           std::unordered_map<long, bool>& ready) const
{
    // Sec. 3.6 / 3.7.3: fuse into a region only while the vehicle is known well relative
    // to its vertices; the local coordinates written now are never corrected later.
    if (!partition_ || options_.max_local_std_m <= 0) return {};
    return [this, &view, &ready](long id) {
        const auto [it, fresh] = ready.try_emplace(id, false);
        if (fresh) it->second = localFusionStd(view, id) <= options_.max_local_std_m;
        return it->second;
    };
}

void DenseSlam::fuseDelayed()
{
    // Step 5a (Sec. 3.7.3): returns kept while no region covered them go into the
    // regions that exist now, at their corrected local coordinates.
    // A stored return that still lies in no region goes to the dense fallback once a
    // region has formed within its reach (it waited because none was near when seen).
    uif::DelayedDenseStore::OutsideSink outside;
    if (hybrid_->options().fallback_max_distance_m > 0)
        outside = [&](const Eigen::Vector2d& sensor, const Eigen::Vector2d& ret) {
            return hybrid_->insertFallbackReturn(sensor, ret, options_.laser_std_range, options_.laser_std_bearing,
                                                 *partition_);
        };
    const auto rep = store_->fuse(
        ekf_, *partition_,
        [&](long rid, const dense::RegionScan& rs) { hybrid_->insertRegionScan(rid, rs, *partition_); }, nullptr,
        outside);
    stats_.delayed_fused += rep.fused;
    stats_.delayed_fused_fallback += rep.fused_outside;
    stats_.delayed_lost += rep.lost_points;
}

void DenseSlam::storeUnassigned(const dense::ScanPoints& pts, const dense::HybridMetricMap::InsertStats& st,
                                double t)
{
    // Step 5b: what no region holds waits in the store as passive states, kept as the
    // sensor measured it (range, bearing in the scan's sensor frame, Eq. 3.25); the tag
    // is the return's index in the scan.
    std::vector<Eigen::Vector2d> z;
    std::vector<long> tags;
    for (size_t i = 0; i < st.unassigned_source.size(); ++i)
        if (!st.unassigned_kept[i])
        {
            z.push_back(pts.rangeBearing(st.unassigned_source[i]));
            tags.push_back(static_cast<long>(st.unassigned_source[i]));
        }
    stats_.returns_dropped += z.size();
    if (!store_ || z.empty()) return;
    const Eigen::Matrix2d R = Eigen::Vector2d(options_.laser_std_range * options_.laser_std_range,
                                              options_.laser_std_bearing * options_.laser_std_bearing)
                                  .asDiagonal();
    const auto& sv = pts.sensor_on_vehicle;
    const auto rep = store_->addScan(ekf_, *partition_, z, R, Eigen::Vector3d(sv.x, sv.y, sv.phi), t, &tags);
    stats_.delayed_stored += rep.stored;
    stats_.returns_dropped -= rep.stored;
    stats_.delayed_outside_potential += rep.outside_potential;
    stats_.delayed_thinned += rep.thinned;
    stats_.delayed_evicted += rep.evicted_points;
    stats_.delayed_lost += rep.lost_points;
}

void DenseSlam::insertDenseScan(const mrpt::obs::CObservation2DRangeScan& scan,
                                const mrpt::math::TPose2D& vehicle,
                                const dense::HybridMetricMap::RegionFilter& accept, double t)
{
    // ScanPoints carries the scan's sensorPose: the layers compose it with `vehicle`.
    const auto pts = dense::ScanPoints::fromRangeScan(scan);
    if (hybrid_ && store_) fuseDelayed();
    if (hybrid_)
    {
        const auto st = hybrid_->insertScan(pts, vehicle, *partition_, accept);
        stats_.returns_stored += st.returns_stored;
        stats_.returns_outside += st.returns_outside;
        stats_.returns_withheld += st.returns_withheld;
        stats_.no_return_beams += st.no_return;
        stats_.failed_readings += pts.skipped;
        ++stats_.dense_scans;
        stats_.returns_fallback += st.returns_fallback;
        stats_.returns_withheld_fallback += st.withheld_fallback;
        const double cell = options_.outside_cell_m;
        for (size_t i = 0; i < st.unassigned.size(); ++i)
        {
            const Eigen::Vector2d& p = st.unassigned[i];
            OutsideSum& c = outside_[dense::pointCellKey(p, cell)];
            c.sum += p;
            ++c.returns;
            c.kept += st.unassigned_kept[i] != 0;
        }
        if (virtual_options_.enabled) createVirtualLandmarks(st.unassigned, t);
        // What the fallback kept is in a dense layer; the rest may wait in the store.
        storeUnassigned(pts, st, t);
    }
    if (classic_) classic_->insertScan(pts, vehicle);
}

std::vector<DenseSlam::OutsideReturnCell> DenseSlam::outsideReturnCells() const
{
    std::vector<std::pair<std::int64_t, OutsideReturnCell>> cells;
    cells.reserve(outside_.size());
    for (const auto& [key, c] : outside_)
        cells.push_back({key, {c.sum / static_cast<double>(c.returns), c.returns, c.kept}});
    std::sort(cells.begin(), cells.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<OutsideReturnCell> out;
    out.reserve(cells.size());
    for (const auto& kv : cells) out.push_back(kv.second);
    return out;
}

void DenseSlam::processDense(const mrpt::obs::CSensoryFrame& frame, double t, bool map_changed)
{
    // Reads the filter only (UIF): nothing below writes to its active states.
    const VirtualLandmarkView view(ekf_, virtual_ids_, options_.pose_landmark_vertices);
    if (partition_ && map_changed) updateRegions(view, frame, t);

    mrpt::system::CTimeLoggerEntry tle(profiler_, "denseslam.5_dense");
    // Every observation of the frame was taken at the frame's pose; the estimate after
    // the frame's update is the best estimate of that pose.
    const Eigen::Vector3d v = ekf_.vehiclePose();
    const mrpt::math::TPose2D vehicle(v[0], v[1], v[2]);
    std::unordered_map<long, bool> ready;
    const dense::HybridMetricMap::RegionFilter accept = fusionGate(view, ready);
    for (const auto& o : frame)
        if (const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o))
            insertDenseScan(*scan, vehicle, accept, t);
    updateMotionLayers(t);
}

void DenseSlam::updateMotionLayers(double t)
{
    if (!motion_ || !hybrid_) return;
    mrpt::system::CTimeLoggerEntry tle(profiler_, "denseslam.6_motion");
    const auto removed = motion_->afterFrame(*hybrid_, *partition_, ekf_, t);
    for (long id : removed) features_.erase(id);
}

void DenseSlam::createVirtualLandmarks(const std::vector<Eigen::Vector2d>& unassigned, double t)
{
    // A Jacobian on a vertex's point, as one on its whole block: a pose landmark's
    // (x, y, phi) gives its point (x, y), the heading column is zero.
    auto onBlock = [&](long lid, const Eigen::Matrix2d& J) {
        Eigen::MatrixXd G = Eigen::MatrixXd::Zero(2, static_cast<Eigen::Index>(ekf_.landmarkBlock(lid).dim));
        G.leftCols<2>() = J;
        return G;
    };
    mrpt::system::CTimeLoggerEntry tle(profiler_, "denseslam.6_virtual");
    const VirtualLandmarkView view(ekf_, virtual_ids_, options_.pose_landmark_vertices);
    const auto proposals =
        ltr::proposeVirtualLandmarks(*partition_, view, unassigned, virtual_options_);
    const double var = virtual_options_.position_std_m * virtual_options_.position_std_m;
    for (const auto& p : proposals)
    {
        // Shallower apexes when the full depth overlaps a region or fails a condition.
        for (double depth = p.depth; depth >= virtual_options_.min_depth_m; depth *= 0.6)
        {
            // v = g(a, b) is augmented like a landmark (Eq. 2.53) with G = [J_a, J_b] on
            // the states of a and b and a small definitional noise in place of R, as a
            // passive state: it follows every correction of a and b, gives nothing back.
            Eigen::Matrix2d Ja, Jb;
            const Eigen::Vector2d v = ltr::virtualApex(view.mean(p.a), view.mean(p.b), p.side, depth, &Ja, &Jb);
            const long id = next_virtual_id_++;
            ekf_.addPassiveFromLandmarks(id, v, {{p.a, onBlock(p.a, Ja)}, {p.b, onBlock(p.b, Jb)}},
                                         var * Eigen::Matrix2d::Identity());
            virtual_ids_.insert(id);
            const VirtualLandmarkView vview(ekf_, virtual_ids_, options_.pose_landmark_vertices);
            if (partition_->tryAddRegion({p.a, p.b, id}, vview, t).accepted())
            {
                ++stats_.virtual_landmarks;
                ++stats_.regions_created;
                break;
            }
            ++stats_.virtual_rejected;
            ekf_.removePassiveState(id);
            virtual_ids_.erase(id);
        }
    }
}

void DenseSlam::dropUnusedVirtualLandmarks()
{
    for (auto it = virtual_ids_.begin(); it != virtual_ids_.end();)
        if (partition_->regionsUsingLandmark(*it).empty())
        {
            if (ekf_.passive().has(*it)) ekf_.removePassiveState(*it);
            it = virtual_ids_.erase(it);
        }
        else
            ++it;
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
        mrpt::system::CTimeLoggerEntry tle(profiler_, "denseslam.2_extract");
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
    mrpt::system::CTimeLoggerEntry tle(profiler_, "denseslam.3_update");
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
        addUpdateCounts(stats_, r);
        return r;
    }
    const auto r = ekf_.updateRangeBearing(obs, sensor);
    ++updates_;
    addUpdateCounts(stats_, r);
    return r;
}

}  // namespace hymm::denseslam
