/**
 * @file DelayedDenseStore.cpp
 * @brief Storing returns (Sec. 3.7.3), budget, and the local estimates of Eq. 3.27-3.30.
 */
#include "hymm/uif/DelayedDenseStore.h"

#include "hymm/uif/local_models.h"
#include "joint_covariance.h"

#include <hymm/core/RangeBearingModel.h>
#include <hymm/core/TimeLogger.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hymm::uif
{
namespace detail
{
Eigen::Vector3d passivePose(const hymm::ekf::EkfSlam& ekf, long passive_id)
{
    Eigen::Vector3d p = ekf.passive().mean(passive_id);
    p[2] = mrpt::math::wrapToPi(p[2]);
    return p;
}

Mat9 jointCovariance(
    const hymm::ekf::EkfSlam& ekf, long passive_id, const std::array<long, 3>& ids,
    hymm::ltr::TriangleFrame::Vertices& v)
{
    std::array<Eigen::Index, 3> off{};
    for (size_t k = 0; k < 3; ++k)
    {
        if (!ekf.hasLandmark(ids[k]) || ekf.landmarkBlock(ids[k]).dim != 2)
            throw std::invalid_argument(
                "DelayedDenseStore: vertex landmark " + std::to_string(ids[k]) +
                " is not a 2D point landmark of the filter");
        off[k] = static_cast<Eigen::Index>(ekf.landmarkBlock(ids[k]).offset);
        v[k] = ekf.mean().segment<2>(off[k]);
    }
    const Eigen::MatrixXd C = ekf.passive().crossCov(passive_id);  // 3 x n_a
    const Eigen::Ref<const Eigen::MatrixXd> P = ekf.cov();  // a view, no copy
    Mat9 S;
    S.topLeftCorner<3, 3>() = ekf.passive().cov(passive_id);
    for (int j = 0; j < 3; ++j)
    {
        S.block<3, 2>(0, 3 + 2 * j) = C.middleCols<2>(off[j]);
        S.block<2, 3>(3 + 2 * j, 0) = C.middleCols<2>(off[j]).transpose();
        for (int k = 0; k < 3; ++k) S.block<2, 2>(3 + 2 * j, 3 + 2 * k) = P.block<2, 2>(off[j], off[k]);
    }
    return 0.5 * (S + S.transpose());
}
}  // namespace detail

namespace
{
void checkNoise(const Eigen::Matrix2d& R)
{
    if (!R.allFinite() || std::abs(R(0, 1) - R(1, 0)) > 1e-12 * (1.0 + R.cwiseAbs().maxCoeff()) ||
        Eigen::LLT<Eigen::Matrix2d>(R).info() != Eigen::Success)
        throw std::invalid_argument(
            "DelayedDenseStore: the sensor noise R must be finite, symmetric and positive definite");
}

/** addScan's arguments beside the noise: finite sensor pose and time, one tag per return,
 *  no earlier than the previous scan. */
void checkScanInput(const std::vector<Eigen::Vector2d>& z, const Eigen::Vector3d& sensor_on_vehicle, double time,
                    const std::vector<long>* tags, double last_time)
{
    if (!sensor_on_vehicle.allFinite() || !std::isfinite(time))
        throw std::invalid_argument("DelayedDenseStore::addScan: non-finite sensor pose or time");
    if (tags && tags->size() != z.size())
        throw std::invalid_argument("DelayedDenseStore::addScan: tags must have one entry per return");
    if (time < last_time)
        throw std::invalid_argument(
            "DelayedDenseStore::addScan: time " + std::to_string(time) + " is before the previous scan's " +
            std::to_string(last_time));
}

/** Keeps m of the points, evenly spread over them (keeps the scan's coverage); returns
 *  how many went. */
size_t thinEvenly(std::vector<StoredPoint>& points, size_t m)
{
    std::vector<StoredPoint> kept;
    const size_t n = points.size();
    for (size_t k = 0; k < m; ++k) kept.push_back(points[k * n / m]);
    points.swap(kept);
    return n - m;
}
}  // namespace

DelayedDenseStore::DelayedDenseStore(const Options& options)
    : options_((options.validate(), options)),
      potential_(options.search_radius_m, options.max_candidate_landmarks),
      next_passive_id_(options.first_passive_id),
      profiler_(options.enable_profiler, "hymm::DelayedDenseStore")
{
}

long DelayedDenseStore::nextPassiveId(const hymm::ekf::EkfSlam& ekf)
{
    // Skips ids another user of the filter's passive states may have taken.
    while (ekf.passive().has(next_passive_id_)) ++next_passive_id_;
    return next_passive_id_++;
}

void DelayedDenseStore::dropFront(hymm::ekf::EkfSlam& ekf)
{
    const StoredScan& s = scans_.front();
    if (ekf.passive().has(s.passive_id)) ekf.removePassiveState(s.passive_id);
    num_points_ -= s.points.size();
    scans_.pop_front();
}

void DelayedDenseStore::dropLostAndOld(hymm::ekf::EkfSlam& ekf, double time, AddReport& rep)
{
    // A reset of the filter drops every passive block: those scans cannot be fused.
    for (auto it = scans_.begin(); it != scans_.end();)
    {
        if (ekf.passive().has(it->passive_id))
        {
            ++it;
            continue;
        }
        rep.lost_points += it->points.size();
        num_points_ -= it->points.size();
        it = scans_.erase(it);
    }
    while (options_.max_age_s > 0 && !scans_.empty() && time - scans_.front().time > options_.max_age_s)
    {
        rep.evicted_points += scans_.front().points.size();
        ++rep.evicted_scans;
        dropFront(ekf);
    }
}

void DelayedDenseStore::releaseUnusedPotentialRegions()
{
    std::vector<long> used;
    for (const auto& s : scans_)
        for (const auto& p : s.points) used.push_back(p.potential_region);
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    potential_.retainOnly(std::move(used));
}

void DelayedDenseStore::selectReturns(
    const hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition,
    const std::vector<Eigen::Vector2d>& z, const Eigen::Vector3d& sensor_on_vehicle,
    const std::vector<long>* tags, StoredScan& scan, AddReport& rep)
{
    // Placed at the current vehicle estimate: the returns a region of the partition
    // already covers (it was created after the caller assigned them, e.g. from a virtual
    // apex: the next fuse() takes them), then those in a potential region, or with
    // require_potential_region off all the others.
    const Eigen::Vector3d vehicle = ekf.vehiclePose();
    const auto keep = [&](size_t i, long potential) {
        scan.points.push_back({z[i], potential, tags ? (*tags)[i] : static_cast<long>(i)});
    };
    std::vector<size_t> uncovered;
    std::vector<Eigen::Vector2d> global;
    for (size_t i = 0; i < z.size(); ++i)
    {
        if (!z[i].allFinite() || !(z[i].x() > 0)) continue;
        const Eigen::Vector2d g = hymm::core::inverseRangeBearing(vehicle, sensor_on_vehicle, z[i]);
        if (partition.findRegion(g))
        {
            keep(i, -1);
            ++rep.in_region;
            continue;
        }
        uncovered.push_back(i);
        global.push_back(g);
    }
    if (options_.require_potential_region)
    {
        potential_.refresh(ekf, partition);
        const std::vector<long> owner = potential_.assign(global, ekf, partition, vehicle.head<2>());
        for (size_t k = 0; k < uncovered.size(); ++k)
            if (owner[k] >= 0) keep(uncovered[k], owner[k]);
    }
    else
    {
        for (const size_t i : uncovered) keep(i, -1);
        rep.without_potential = uncovered.size();
    }
    rep.outside_potential = z.size() - scan.points.size();
}

DelayedDenseStore::AddReport DelayedDenseStore::addScan(
    hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition,
    const std::vector<Eigen::Vector2d>& z, const Eigen::Matrix2d& R,
    const Eigen::Vector3d& sensor_on_vehicle, double time, const std::vector<long>* tags)
{
    AddReport rep;
    rep.offered = z.size();
    if (!options_.enabled) return rep;
    core::TimedSection tle(profiler_, "uif.addScan");
    checkNoise(R);
    checkScanInput(z, sensor_on_vehicle, time, tags, last_time_);
    last_time_ = time;

    // 1. Forget scans the filter no longer carries, and scans that are too old.
    dropLostAndOld(ekf, time, rep);

    // 2. Which returns wait here (Sec. 3.7.3).
    StoredScan scan;
    selectReturns(ekf, partition, z, sensor_on_vehicle, tags, scan, rep);

    // 3. A scan larger than the whole budget is thinned evenly (keeps its coverage).
    if (scan.points.size() > options_.max_stored_points)
        rep.thinned = thinEvenly(scan.points, options_.max_stored_points);
    if (scan.points.empty())
    {
        releaseUnusedPotentialRegions();
        return rep;
    }

    // 4. Budget: oldest scans go first.
    while (!scans_.empty() && (num_points_ + scan.points.size() > options_.max_stored_points ||
                               scans_.size() + 1 > options_.max_stored_scans))
    {
        rep.evicted_points += scans_.front().points.size();
        ++rep.evicted_scans;
        dropFront(ekf);
    }

    // 5. The passive copy of the vehicle pose (Eq. 2.53 with G_v = I, no noise): it gets
    //    P_vv and P_v* now and every later correction through the UIF.
    scan.scan_id = next_scan_id_++;
    scan.passive_id = nextPassiveId(ekf);
    scan.time = time;
    scan.sensor = sensor_on_vehicle;
    scan.R = 0.5 * (R + R.transpose());
    ekf.addPassiveFromVehicle(scan.passive_id, ekf.vehiclePose(), Eigen::Matrix3d::Identity(),
                              Eigen::Matrix3d::Zero());
    rep.stored = scan.points.size();
    rep.scan_id = scan.scan_id;
    num_points_ += scan.points.size();
    scans_.push_back(std::move(scan));
    releaseUnusedPotentialRegions();
    return rep;
}

void DelayedDenseStore::clear(hymm::ekf::EkfSlam& ekf)
{
    while (!scans_.empty()) dropFront(ekf);
    potential_.clear();
}

LocalEstimate<2> DelayedDenseStore::localPointEstimate(
    const hymm::ekf::EkfSlam& ekf, const StoredScan& scan, size_t i,
    const std::array<long, 3>& vertex_ids) const
{
    if (i >= scan.points.size()) throw std::out_of_range("DelayedDenseStore: point index out of range");
    hymm::ltr::TriangleFrame::Vertices v;
    const detail::Mat9 S = detail::jointCovariance(ekf, scan.passive_id, vertex_ids, v);
    const hymm::ltr::TriangleFrame frame(v);  // throws on a degenerate triangle
    PointLocalJacobians J;
    LocalEstimate<2> out;
    out.mean = pointLocal(detail::passivePose(ekf, scan.passive_id), scan.sensor, scan.points[i].z, frame, &J);
    Eigen::Matrix<double, 2, 9> A;
    A << J.pose, J.vertices;
    // First-order propagation of (x_s, L, z); z is independent of every filter state.
    const Eigen::Matrix2d C = A * S * A.transpose() + J.z * scan.R * J.z.transpose();
    out.cov = 0.5 * (C + C.transpose());
    return out;
}

LocalEstimate<3> DelayedDenseStore::localVehiclePoseEstimate(
    const hymm::ekf::EkfSlam& ekf, const StoredScan& scan, const std::array<long, 3>& vertex_ids) const
{
    hymm::ltr::TriangleFrame::Vertices v;
    const detail::Mat9 S = detail::jointCovariance(ekf, scan.passive_id, vertex_ids, v);
    const hymm::ltr::TriangleFrame frame(v);
    Mat3 Jp;
    Mat36 Jv;
    LocalEstimate<3> out;
    out.mean = localVehiclePose(detail::passivePose(ekf, scan.passive_id), frame, &Jp, &Jv);
    Eigen::Matrix<double, 3, 9> A;
    A << Jp, Jv;
    const Mat3 C = A * S * A.transpose();  // P_vv^L of Eq. 3.30
    out.cov = 0.5 * (C + C.transpose());
    return out;
}

}  // namespace hymm::uif
