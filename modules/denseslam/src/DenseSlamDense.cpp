/**
 * @file DenseSlamDense.cpp
 * @brief Steps 4-7 of the pipeline (DenseSlam.h): regions, the scan into the dense
 *        layers with the delayed store and the fallback, virtual landmarks, the motion
 *        layers and the HLL search. Reads the filter only (UIF, Sec. 3.2), except where
 *        the class comment says.
 */
#include "hymm/denseslam/DenseSlam.h"
#include "hymm/denseslam/VirtualLandmarkView.h"

#include <hymm/dense/ScanPoints.h>
#include <hymm/core/TimeLogger.h>
#include <hymm/dense/geometry.h>
#include <hymm/ltr/position_error.h>
#include <hymm/uif/DelayedDenseStore.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hymm::denseslam
{
void DenseSlam::searchHighLevelLandmarks(double t)
{
    if (!hll_->due(t)) return;
    core::TimedSection tle(profiler_, "denseslam.7_hll_search");
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
    core::TimedSection tle(profiler_, "denseslam.4_regions");
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
    stats_.add(rep);
}

void DenseSlam::storeUnassigned(const dense::ScanPoints& pts, const dense::HybridMetricMap::InsertStats& st,
                                double t)
{
    // Step 5d: what no region holds waits in the store as passive states, kept as the
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
    if (!store_ || z.empty())
    {
        stats_.returns_dropped += z.size();
        return;
    }
    const Eigen::Matrix2d R = Eigen::Vector2d(options_.laser_std_range * options_.laser_std_range,
                                              options_.laser_std_bearing * options_.laser_std_bearing)
                                  .asDiagonal();
    const auto& sv = pts.sensor_on_vehicle;
    const auto rep = store_->addScan(ekf_, *partition_, z, R, Eigen::Vector3d(sv.x, sv.y, sv.phi), t, &tags);
    stats_.add(rep);
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
        stats_.add(st, pts.skipped);
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

    core::TimedSection tle(profiler_, "denseslam.5_dense");
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
    core::TimedSection tle(profiler_, "denseslam.6_motion");
    const auto removed = motion_->afterFrame(*hybrid_, *partition_, ekf_, t);
    for (long id : removed) features_.erase(id);
}

void DenseSlam::createVirtualLandmarks(const std::vector<Eigen::Vector2d>& unassigned, double t)
{
    core::TimedSection tle(profiler_, "denseslam.6_virtual");
    const VirtualLandmarkView view(ekf_, virtual_ids_, options_.pose_landmark_vertices);
    for (const auto& p : ltr::proposeVirtualLandmarks(*partition_, view, unassigned, virtual_options_))
        // Shallower apexes when the full depth overlaps a region or fails a condition.
        for (double depth = p.depth; depth >= virtual_options_.min_depth_m; depth *= 0.6)
            if (addVirtualRegion(p, depth, t)) break;
}

bool DenseSlam::addVirtualRegion(const ltr::VirtualLandmarkProposal& p, double depth, double t)
{
    // A Jacobian on a vertex's point, as one on its whole block: a pose landmark's
    // (x, y, phi) gives its point (x, y), the heading column is zero.
    auto onBlock = [&](long lid, const Eigen::Matrix2d& J) {
        Eigen::MatrixXd G = Eigen::MatrixXd::Zero(2, static_cast<Eigen::Index>(ekf_.landmarkBlock(lid).dim));
        G.leftCols<2>() = J;
        return G;
    };
    // v = g(a, b) is augmented like a landmark (Eq. 2.53) with G = [J_a, J_b] on the states
    // of a and b and a small definitional noise in place of R, as a passive state: it
    // follows every correction of a and b, gives nothing back.
    const VirtualLandmarkView view(ekf_, virtual_ids_, options_.pose_landmark_vertices);
    Eigen::Matrix2d Ja, Jb;
    const Eigen::Vector2d v = ltr::virtualApex(view.mean(p.a), view.mean(p.b), p.side, depth, &Ja, &Jb);
    const double var = virtual_options_.position_std_m * virtual_options_.position_std_m;
    const long id = next_virtual_id_++;
    ekf_.addPassiveFromLandmarks(id, v, {{p.a, onBlock(p.a, Ja)}, {p.b, onBlock(p.b, Jb)}},
                                 var * Eigen::Matrix2d::Identity());
    virtual_ids_.insert(id);
    const VirtualLandmarkView vview(ekf_, virtual_ids_, options_.pose_landmark_vertices);
    if (partition_->tryAddRegion({p.a, p.b, id}, vview, t).accepted())
    {
        ++stats_.virtual_landmarks;
        ++stats_.regions_created;
        return true;
    }
    // The conditions need the apex's covariance with the other vertices, which the
    // filter computes: a refused apex leaves it again.
    ++stats_.virtual_rejected;
    ekf_.removePassiveState(id);
    virtual_ids_.erase(id);
    return false;
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

}  // namespace hymm::denseslam
