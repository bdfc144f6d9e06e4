/**
 * @file DelayedDenseStoreFuse.cpp
 * @brief Fusing stored returns into the regions that now cover them (Sec. 3.7.3: "once
 *        the local vehicle uncertainty is reduced, a new LTR is initialised, the
 *        observations stored are fused into the local region and eliminated").
 */
#include "hymm/uif/DelayedDenseStore.h"

#include "hymm/uif/local_models.h"
#include "joint_covariance.h"

#include <hymm/core/RangeBearingModel.h>
#include <hymm/dense/geometry.h>
#include <hymm/ltr/AffineRegionMap.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <unordered_map>

namespace hymm::uif
{
namespace
{
/** A clipped beam whose far end is this close to 1 reaches the return. */
constexpr double kEndParamTol = 1e-9;

/** What fuse() needs of one region, computed once per call. */
struct RegionInfo
{
    const hymm::ltr::Region* region = nullptr;
    std::optional<hymm::ltr::AffineRegionMap> to_current;  //!< nullopt: degenerate
};

/** Beam from the sensor to the return, in the reference frame, clipped to the triangle. */
std::optional<hymm::dense::FreeRay> referenceRay(
    const Eigen::Vector2d& sensor_ref, const Eigen::Vector2d& hit_ref, const hymm::ltr::Region& r)
{
    const auto iv = hymm::dense::clipSegmentToTriangle(sensor_ref, hit_ref, r.reference);
    if (!iv) return std::nullopt;
    const Eigen::Vector2d d = hit_ref - sensor_ref;
    const bool to_end = iv->t1 >= 1.0 - kEndParamTol;
    return hymm::dense::FreeRay{
        sensor_ref + iv->t0 * d, to_end ? hit_ref : Eigen::Vector2d(sensor_ref + iv->t1 * d), to_end};
}
}  // namespace

DelayedDenseStore::FuseReport DelayedDenseStore::fuse(
    hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition, const RegionSink& sink,
    std::vector<FusedPoint>* fused, const OutsideSink& outside)
{
    FuseReport rep;
    if (!options_.enabled || scans_.empty()) return rep;
    mrpt::system::CTimeLoggerEntry tle(profiler_, "uif.fuse");
    std::unordered_map<long, RegionInfo> regions;
    const auto info = [&](long rid) -> const RegionInfo&
    {
        auto it = regions.find(rid);
        if (it != regions.end()) return it->second;
        RegionInfo ri;
        ri.region = &partition.region(rid);
        try
        {
            ri.to_current = partition.referenceToCurrent(rid);
        }
        catch (const std::invalid_argument&)
        {
            // The filter folded this triangle: no frame to map into; keep the returns.
        }
        return regions.emplace(rid, std::move(ri)).first->second;
    };

    for (StoredScan& scan : scans_)
    {
        if (!ekf.passive().has(scan.passive_id))
        {
            rep.lost_points += scan.points.size();
            num_points_ -= scan.points.size();
            scan.points.clear();
            continue;
        }
        // Every return of the scan is placed with the CURRENT (UIF-corrected) passive pose.
        const Eigen::Vector3d pose = detail::passivePose(ekf, scan.passive_id);
        const Eigen::Vector2d sensor = hymm::core::sensorGlobalPose(pose, scan.sensor).head<2>();
        std::map<long, hymm::dense::RegionScan> out;
        std::map<long, std::pair<detail::Mat9, hymm::ltr::TriangleFrame::Vertices>> joint;
        std::vector<StoredPoint> keep;
        for (size_t i = 0; i < scan.points.size(); ++i)
        {
            const StoredPoint& p = scan.points[i];
            const Eigen::Vector2d g = hymm::core::inverseRangeBearing(pose, scan.sensor, p.z);
            const auto rid = partition.findRegion(g);
            if (!rid)
            {
                if (outside && outside(sensor, g))
                {
                    ++rep.fused_outside;
                    continue;
                }
                keep.push_back(p);
                continue;
            }
            const RegionInfo& ri = info(*rid);
            if (!ri.to_current)
            {
                ++rep.degenerate;
                keep.push_back(p);
                continue;
            }
            // Reference-frame position: the same affine map HybridMetricMap uses, so a
            // delayed return is stored exactly as if it had been seen now from `pose`.
            hymm::dense::RegionScan& rs = out[*rid];
            const Eigen::Vector2d ref = ri.to_current->inverseMapPoint(g);
            rs.hits.push_back(ref);
            if (options_.fuse_free_space && ri.region->creation_time > scan.time)
                if (auto ray = referenceRay(ri.to_current->inverseMapPoint(sensor), ref, *ri.region))
                    rs.rays.push_back(*ray);
            if (fused)
            {
                auto jit = joint.find(*rid);
                if (jit == joint.end())
                {
                    hymm::ltr::TriangleFrame::Vertices v;
                    const detail::Mat9 S =
                        detail::jointCovariance(ekf, scan.passive_id, ri.region->vertex_ids, v);
                    jit = joint.emplace(*rid, std::make_pair(S, v)).first;
                }
                FusedPoint fp;
                fp.region_id = *rid;
                fp.vertex_ids = ri.region->vertex_ids;
                fp.scan_id = scan.scan_id;
                fp.tag = p.tag;
                fp.time = scan.time;
                fp.reference = ref;
                const hymm::ltr::TriangleFrame frame(jit->second.second);
                PointLocalJacobians J;
                fp.local.mean = pointLocal(pose, scan.sensor, p.z, frame, &J);
                Eigen::Matrix<double, 2, 9> A;
                A << J.pose, J.vertices;
                const Eigen::Matrix2d C =
                    A * jit->second.first * A.transpose() + J.z * scan.R * J.z.transpose();
                fp.local.cov = 0.5 * (C + C.transpose());
                fused->push_back(std::move(fp));
            }
        }
        for (auto& [rid, rs] : out)
        {
            const hymm::ltr::AffineRegionMap& to_current = *regions.at(rid).to_current;
            rs.sensor = to_current.inverseMapPoint(sensor);
            // What HybridMetricMap::insertScan gives a direct scan: the layers that model
            // the beam (SOG, particles) need the noise and the frame's linear part.
            rs.range_std_m = std::sqrt(scan.R(0, 0));
            rs.bearing_std_rad = std::sqrt(scan.R(1, 1));
            rs.to_reference_linear = to_current.inverse().linear();
            rep.fused += rs.hits.size();
            rep.regions.push_back(rid);
            sink(rid, rs);
        }
        num_points_ -= scan.points.size() - keep.size();
        scan.points.swap(keep);
    }

    // Scans with nothing left release their passive block (Sec. 3.7.3: "eliminated from
    // the state vector").
    for (auto it = scans_.begin(); it != scans_.end();)
    {
        if (!it->points.empty())
        {
            ++it;
            continue;
        }
        if (ekf.passive().has(it->passive_id))
        {
            ekf.removePassiveState(it->passive_id);
            ++rep.scans_released;
        }
        it = scans_.erase(it);
    }
    std::sort(rep.regions.begin(), rep.regions.end());
    rep.regions.erase(std::unique(rep.regions.begin(), rep.regions.end()), rep.regions.end());
    releaseUnusedPotentialRegions();
    return rep;
}

}  // namespace hymm::uif
