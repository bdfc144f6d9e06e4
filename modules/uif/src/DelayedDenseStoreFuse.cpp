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
#include <hymm/core/TimeLogger.h>
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

/** The frames of the regions one fuse() call touches, each looked up once. */
class RegionFrames
{
   public:
    explicit RegionFrames(const hymm::ltr::RegionPartition& partition) : partition_(partition) {}

    const RegionInfo& get(long rid)
    {
        auto it = regions_.find(rid);
        if (it != regions_.end()) return it->second;
        RegionInfo ri;
        ri.region = &partition_.region(rid);
        try
        {
            ri.to_current = partition_.referenceToCurrent(rid);
        }
        catch (const std::invalid_argument&)
        {
            // The filter folded this triangle: no frame to map into; keep the returns.
        }
        return regions_.emplace(rid, std::move(ri)).first->second;
    }

   private:
    const hymm::ltr::RegionPartition& partition_;
    std::unordered_map<long, RegionInfo> regions_;
};

/** Fuses the returns of the stored scans, one scan at a time, into the regions that
 *  cover them now (DelayedDenseStore::fuse). */
class ScanFuser
{
   public:
    using Store = DelayedDenseStore;

    ScanFuser(hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition, bool free_space,
              const Store::RegionSink& sink, std::vector<Store::FusedPoint>* fused,
              const Store::OutsideSink& outside, Store::FuseReport& rep)
        : ekf_(ekf), partition_(partition), frames_(partition), free_space_(free_space), sink_(sink),
          fused_(fused), outside_(outside), rep_(rep)
    {
    }

    /** Places every return of `scan` with the CURRENT (UIF-corrected) passive pose;
     *  returns the ones that stay stored (in no region, or in a folded one). */
    std::vector<StoredPoint> fuseScan(const StoredScan& scan)
    {
        const Eigen::Vector3d pose = detail::passivePose(ekf_, scan.passive_id);
        const Eigen::Vector2d sensor = hymm::core::sensorGlobalPose(pose, scan.sensor).head<2>();
        std::map<long, hymm::dense::RegionScan> out;
        joint_.clear();
        std::vector<StoredPoint> keep;
        for (size_t i = 0; i < scan.points.size(); ++i)
        {
            const StoredPoint& p = scan.points[i];
            const Eigen::Vector2d g = hymm::core::inverseRangeBearing(pose, scan.sensor, p.z);
            const auto rid = partition_.findRegion(g);
            if (!rid)
            {
                if (outside_ && outside_(sensor, g))
                {
                    ++rep_.fused_outside;
                    continue;
                }
                keep.push_back(p);
                continue;
            }
            const RegionInfo& ri = frames_.get(*rid);
            if (!ri.to_current)
            {
                ++rep_.degenerate;
                keep.push_back(p);
                continue;
            }
            // Reference-frame position: the same affine map HybridMetricMap uses, so a
            // delayed return is stored exactly as if it had been seen now from `pose`.
            hymm::dense::RegionScan& rs = out[*rid];
            const Eigen::Vector2d ref = ri.to_current->inverseMapPoint(g);
            rs.hits.push_back(ref);
            if (free_space_ && ri.region->creation_time > scan.time)
                if (auto ray = referenceRay(ri.to_current->inverseMapPoint(sensor), ref, *ri.region))
                    rs.rays.push_back(*ray);
            if (fused_) fused_->push_back(fusedPoint(scan, p, pose, *rid, *ri.region, ref));
        }
        for (auto& [rid, rs] : out) handOut(rid, rs, scan, sensor);
        return keep;
    }

   private:
    /** A fused return with its local Gaussian: the joint covariance of the scan's pose and
     *  the region's vertices (computed once per region and scan) through the Jacobians
     *  of the local coordinates, plus the measurement noise. */
    Store::FusedPoint fusedPoint(
        const StoredScan& scan, const StoredPoint& p, const Eigen::Vector3d& pose, long rid,
        const hymm::ltr::Region& region, const Eigen::Vector2d& ref)
    {
        auto jit = joint_.find(rid);
        if (jit == joint_.end())
        {
            hymm::ltr::TriangleFrame::Vertices v;
            const detail::Mat9 S = detail::jointCovariance(ekf_, scan.passive_id, region.vertex_ids, v);
            jit = joint_.emplace(rid, std::make_pair(S, v)).first;
        }
        Store::FusedPoint fp;
        fp.region_id = rid;
        fp.vertex_ids = region.vertex_ids;
        fp.scan_id = scan.scan_id;
        fp.tag = p.tag;
        fp.time = scan.time;
        fp.reference = ref;
        const hymm::ltr::TriangleFrame frame(jit->second.second);
        PointLocalJacobians J;
        fp.local.mean = pointLocal(pose, scan.sensor, p.z, frame, &J);
        Eigen::Matrix<double, 2, 9> A;
        A << J.pose, J.vertices;
        const Eigen::Matrix2d C = A * jit->second.first * A.transpose() + J.z * scan.R * J.z.transpose();
        fp.local.cov = 0.5 * (C + C.transpose());
        return fp;
    }

    /** Gives region `rid` the returns of `scan` it covers, as HybridMetricMap::insertScan
     *  gives a direct scan: the layers that model the beam (SOG, particles) need the
     *  noise and the frame's linear part. */
    void handOut(long rid, hymm::dense::RegionScan& rs, const StoredScan& scan, const Eigen::Vector2d& sensor)
    {
        const hymm::ltr::AffineRegionMap& to_current = *frames_.get(rid).to_current;
        rs.sensor = to_current.inverseMapPoint(sensor);
        rs.range_std_m = std::sqrt(scan.R(0, 0));
        rs.bearing_std_rad = std::sqrt(scan.R(1, 1));
        rs.to_reference_linear = to_current.inverse().linear();
        rep_.fused += rs.hits.size();
        rep_.regions.push_back(rid);
        sink_(rid, rs);
    }

    hymm::ekf::EkfSlam& ekf_;
    const hymm::ltr::RegionPartition& partition_;
    RegionFrames frames_;
    const bool free_space_;
    const Store::RegionSink& sink_;
    std::vector<Store::FusedPoint>* fused_;
    const Store::OutsideSink& outside_;
    Store::FuseReport& rep_;
    /** Per scan: joint covariance of its pose and a region's vertices, with the vertices. */
    std::map<long, std::pair<detail::Mat9, hymm::ltr::TriangleFrame::Vertices>> joint_;
};
}  // namespace

DelayedDenseStore::FuseReport DelayedDenseStore::fuse(
    hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition, const RegionSink& sink,
    std::vector<FusedPoint>* fused, const OutsideSink& outside)
{
    FuseReport rep;
    if (!options_.enabled || scans_.empty()) return rep;
    core::TimedSection tle(profiler_, "uif.fuse");
    ScanFuser fuser(ekf, partition, options_.fuse_free_space, sink, fused, outside, rep);
    for (StoredScan& scan : scans_)
    {
        if (!ekf.passive().has(scan.passive_id))
        {
            rep.lost_points += scan.points.size();
            num_points_ -= scan.points.size();
            scan.points.clear();
            continue;
        }
        std::vector<StoredPoint> keep = fuser.fuseScan(scan);
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
