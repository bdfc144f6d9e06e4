/**
 * @file DelayedDenseStore.h
 * @brief Delayed dense initialisation with Unidirectional Information Flow (thesis
 *        Sec. 3.7.3, Eq. 3.25-3.30, Fig. 3.15-3.16).
 *
 * Laser returns that fall in no Local Triangular Region yet are kept here until a region
 * covers them, then fused into that region's dense layers with corrected local
 * coordinates. While waiting, they receive every EKF correction through the UIF (passive
 * states, Sec. 3.7.1) and never give information back, so the active EKF states are
 * bitwise identical with or without the store.
 *
 * Representation (the choice and why). The thesis augments the state with the local
 * vehicle pose x_v^j = (alpha, beta, gamma) in a potential region j and every return
 * x_d^j in local coordinates (Eq. 3.25-3.26), with P_dd and P_vd from Eq. 3.30. Every
 * return depends on the active states only through the vehicle pose at the time it was
 * seen (and, in local coordinates, through the three vertices, which are active states).
 * So the store keeps, per stored scan,
 *  - ONE passive 3-DOF EKF block: a copy of the global vehicle pose at observation time
 *    (EkfSlam::addPassiveFromVehicle with G_v = I and zero noise), which the filter
 *    propagates and corrects on every predict/update/augment/prune with its full
 *    cross-covariance to the active states (UIF: it never feeds back);
 *  - the raw (range, bearing) of each return, with the scan's sensor noise R and the
 *    sensor mounting pose.
 * A return's local coordinates, their covariance and their cross-covariance with the
 * active states are functions of that block, the current vertex estimates and z, and are
 * derived exactly (first order) when needed:
 *     l = D^{-1} (g(x_s, z) - L1),   J = [dl/dx_s, dl/dL1..3]  (local_models.h)
 *     P_ll = J [P_ss P_sL; P_Ls P_LL] J^T + (dl/dz) R (dl/dz)^T,   P_la = J [P_sa; P_La].
 * This is the thesis' model (per-point covariance and cross-covariance with the actives,
 * no point-point terms kept) with the local pose expressed through the global pose and
 * the vertices instead of being stored: (alpha, beta, gamma) = f(x_s, L) (Eq. 3.27-3.28)
 * is available from localVehiclePoseEstimate(). Why this way:
 *  - the filter carries 3 n_a + 9 numbers per scan instead of 2 n_a + 4 per return (a
 *    360-beam scan would cost 240x more), and its per-update cost grows with the number
 *    of stored scans, not returns;
 *  - the global pose is estimated by the EKF exactly like the vehicle (no extra model),
 *    whereas a stored local pose would need a Jacobian re-linearised at every update;
 *  - the potential region may differ from the region the partition finally creates: the
 *    global pose lets the store fuse into whichever region covers the return.
 *
 * Per-frame use (pipeline, after the EKF update and partition.update(view, t)):
 *     store.fuse(ekf, partition, sink);            // fuse what a region now covers
 *     st = hybrid.insertScan(scan, pose, partition);
 *     // the raw (range, bearing) of the returns in no region, scan.rangeBearing(i) for
 *     // i in st.unassigned_source: the measurement itself, never a global point
 *     store.addScan(ekf, partition, z, R, sensor_on_vehicle, t, &tags);
 * `sink(region_id, region_scan)` receives reference-frame content for one region (see
 * fuse()); with HybridMetricMap it forwards to that region's LocalDenseMap::insert.
 *
 * Budget: at most max_stored_points returns and max_stored_scans passive blocks; when a
 * new scan would exceed either, the OLDEST scans are dropped first (their passive blocks
 * removed from the EKF), since old returns are the least likely to be covered by a region
 * growing around the vehicle. A single scan larger than max_stored_points is thinned
 * evenly. Scans older than max_age_s (if > 0) are dropped too.
 *
 * Costs per frame: fuse() is O(stored returns) (one grid lookup each) plus O(n_a) per
 * scan that fuses (removing its passive rows); addScan() is O(returns x potential regions)
 * plus O(n_a) for the new passive block and, when new potential regions are needed, O(n)
 * over landmark ids. The EKF's own update cost grows by O(3 S n_a m) for S stored scans.
 */
#pragma once

#include <hymm/core/TimeLogger.h>
#include <hymm/core/OptionTable.h>
#include <hymm/dense/RegionScan.h>
#include <hymm/ekf/EkfSlam.h>
#include <hymm/ltr/RegionPartition.h>
#include <hymm/uif/PotentialRegionSet.h>
#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Core>

#include <array>
#include <deque>
#include <functional>
#include <string>
#include <vector>

namespace mrpt::serialization
{
class CArchive;
}

namespace hymm::uif
{
/** One stored return: its raw measurement, relative to the scan's passive pose block. */
struct StoredPoint
{
    Eigen::Vector2d z = Eigen::Vector2d::Zero();  //!< (range [m], bearing [rad])
    /** Potential region it was stored relative to; -1 when it was stored without one
     *  (already inside a region of the partition, or require_potential_region off). */
    long potential_region = -1;
    long tag = -1;               //!< caller's label (e.g. beam index), returned at fusion
};

/** One stored scan: a passive copy of the vehicle pose at observation time + returns. */
struct StoredScan
{
    long scan_id = -1;
    long passive_id = -1;  //!< id of its passive block in the EKF
    double time = 0;       //!< [s] observation time
    Eigen::Vector3d sensor = Eigen::Vector3d::Zero();  //!< sensor pose on the vehicle
    Eigen::Matrix2d R = Eigen::Matrix2d::Identity();   //!< range-bearing noise covariance
    std::vector<StoredPoint> points;
};

/** Mean and covariance of a local quantity. */
template <int N>
struct LocalEstimate
{
    Eigen::Matrix<double, N, 1> mean;
    Eigen::Matrix<double, N, N> cov;
};

class DelayedDenseStore
{
public:
    /** Ini section [DelayedDenseStore]; unknown keys are errors, absent keys keep the
     *  defaults below. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        /** Off: addScan() stores nothing and fuse() does nothing (the pipeline behaves as
         *  without the store: unassigned returns are discarded). */
        bool enabled = false;
        /** On (thesis Sec. 3.7.3): a return in no region is stored only inside a potential
         *  region (a triangle of real landmarks near the vehicle, PotentialRegionSet).
         *  Off: every return in no region is stored ("sensor information cannot be
         *  discarded"), so it can also reach regions no potential region predicted
         *  (virtual apexes, Sec. 3.5.1; landmarks confirmed later; triangles beyond the
         *  max_candidate_landmarks nearest). The representation does not need the
         *  potential region: each return hangs off its scan's passive global pose. */
        bool require_potential_region = true;
        size_t max_stored_points = 20000;  //!< returns kept at most (>= 1)
        size_t max_stored_scans = 50;      //!< passive EKF blocks at most (>= 1)
        double max_age_s = 0.0;            //!< [s] older scans are dropped; 0 = no limit
        double search_radius_m = 25.0;     //!< [m] potential-region vertices near the vehicle
        int max_candidate_landmarks = 8;   //!< nearest landmarks tried (>= 3; k^3/6 triples)
        /** Also fuse the free-space beam (sensor -> return) into the covering region when
         *  that region was created after the scan (older regions already got it). */
        bool fuse_free_space = true;
        long first_passive_id = 1000000000;  //!< passive ids are taken from here upwards
        bool enable_profiler = false;        //!< CTimeLogger sections "uif.*"

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        /** Throws std::invalid_argument naming the section, key and value. */
        void validate(const std::string& section = "DelayedDenseStore") const;
    };

    /** Outcome of one addScan(). offered = stored + outside_potential + thinned. */
    struct AddReport
    {
        size_t offered = 0;
        size_t stored = 0;
        size_t outside_potential = 0;  //!< in no potential region: discarded (Sec. 3.7.3)
        /** Stored although in no potential region because a region of the partition
         *  already covers them (created after the returns were assigned, e.g. from a
         *  virtual apex): fused by the next fuse(). Included in `stored`. */
        size_t in_region = 0;
        /** Stored outside every potential region (require_potential_region off).
         *  Included in `stored`. */
        size_t without_potential = 0;
        size_t thinned = 0;            //!< dropped because the scan alone exceeds the budget
        size_t evicted_points = 0;     //!< older returns dropped for the budget / age
        size_t evicted_scans = 0;
        size_t lost_points = 0;        //!< their passive block vanished (EKF reset)
        long scan_id = -1;             //!< -1 if nothing was stored
    };

    /** One fused return (filled only if requested, see fuse()). */
    struct FusedPoint
    {
        long region_id = -1;
        std::array<long, 3> vertex_ids{{-1, -1, -1}};
        long scan_id = -1;
        long tag = -1;
        double time = 0;                  //!< observation time of its scan
        Eigen::Vector2d reference;        //!< position stored in the region's reference frame
        LocalEstimate<2> local;           //!< local coordinates in the region at fusion
    };

    struct FuseReport
    {
        size_t fused = 0;          //!< returns handed to the sink
        size_t scans_released = 0; //!< scans emptied (passive blocks removed)
        size_t lost_points = 0;    //!< their passive block vanished (EKF reset)
        size_t degenerate = 0;     //!< in a region whose current triangle is no frame: kept
        /** In no region, taken by the OutsideSink (e.g. the dense fallback): they leave the
         *  store like fused ones. Not included in `fused`. */
        size_t fused_outside = 0;
        std::vector<long> regions; //!< regions that received returns, sorted
    };

    /** Receives content for region `region_id` in its reference frame (one call per
     *  region and stored scan with fused returns). */
    using RegionSink = std::function<void(long region_id, const hymm::dense::RegionScan& scan)>;
    /** Offered a stored return that lies in no region, at its CURRENT global estimate with
     *  the sensor's current global position; returns true if it kept the return (which
     *  then leaves the store), false to leave it waiting. */
    using OutsideSink = std::function<bool(const Eigen::Vector2d& sensor, const Eigen::Vector2d& ret)>;

    /** Throws std::invalid_argument on invalid options. */
    explicit DelayedDenseStore(const Options& options);
    DelayedDenseStore(const DelayedDenseStore&) = delete;
    DelayedDenseStore& operator=(const DelayedDenseStore&) = delete;

    const Options& options() const { return options_; }
    /** Saved run state (hymm-slam --save-state): every member a later step reads, bit
     *  for bit; loadState() replaces them (options come from the config). Throws
     *  std::runtime_error on a corrupt or truncated state. Source: DelayedDenseStoreState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

    /**
     * Stores returns of one scan seen from the CURRENT vehicle estimate of `ekf` (call
     * right after the update of the frame). `z` are raw (range, bearing) in the sensor
     * frame, `R` their noise (PD), `sensor_on_vehicle` = (x, y, yaw). Returns inside a
     * region of `partition` are kept for the next fuse(); with require_potential_region,
     * returns outside every potential region are discarded. `tags`, if given, has one
     * entry per return.
     * Enforces the budget, adds one passive block. Throws on invalid R, sizes or
     * non-monotonic time; non-finite or non-positive-range returns are skipped
     * (counted as outside_potential).
     */
    AddReport addScan(
        hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition,
        const std::vector<Eigen::Vector2d>& z, const Eigen::Matrix2d& R,
        const Eigen::Vector3d& sensor_on_vehicle, double time, const std::vector<long>* tags = nullptr);

    /**
     * Fuses every stored return whose CURRENT estimate (passive pose, z) lies in a region
     * of `partition` (current triangles must be up to date): its global estimate is
     * mapped into the region's reference frame (the inverse of referenceToCurrent, as
     * HybridMetricMap does) and handed to `sink` as RegionScan hits (plus the beam as a
     * FreeRay ending at the hit, clipped to the reference triangle, if fuse_free_space
     * and the region was created after the scan). Each RegionScan carries the scan's
     * range / bearing noise (square roots of the diagonal of its R) and the region's
     * current -> reference linear map, as HybridMetricMap::insertScan fills them, so the
     * SOG and particle layers model a delayed return like a direct one. Fused returns
     * leave the store; scans left empty release their passive block. If `fused` is
     * given, each fused return's local coordinates and full covariance (including the
     * vertices) are appended. With `outside`, a return in no region is offered to it
     * (counted in FuseReport::fused_outside when taken): the fusion rule that lets the
     * returns of scans seen before any region was near reach the dense fallback once a
     * region forms within its reach.
     */
    FuseReport fuse(
        hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition, const RegionSink& sink,
        std::vector<FusedPoint>* fused = nullptr, const OutsideSink& outside = {});

    /** Drops everything and removes the store's passive blocks from `ekf`. */
    void clear(hymm::ekf::EkfSlam& ekf);

    // --- estimates -----------------------------------------------------------------
    /** Local coordinates of return `i` of `scan` in the triangle of landmarks `vertex_ids`,
     *  with the full first-order covariance (pose, vertices and their correlation, R).
     *  Throws if the passive block or a vertex is missing or the triangle is degenerate. */
    LocalEstimate<2> localPointEstimate(
        const hymm::ekf::EkfSlam& ekf, const StoredScan& scan, size_t i,
        const std::array<long, 3>& vertex_ids) const;
    /** Local vehicle pose (alpha, beta, gamma) of `scan` in the triangle (Eq. 3.27-3.28)
     *  with its covariance P_vv^L. */
    LocalEstimate<3> localVehiclePoseEstimate(
        const hymm::ekf::EkfSlam& ekf, const StoredScan& scan,
        const std::array<long, 3>& vertex_ids) const;

    // --- access ----------------------------------------------------------------------
    const std::deque<StoredScan>& scans() const { return scans_; }
    size_t numStoredPoints() const { return num_points_; }
    size_t numStoredScans() const { return scans_.size(); }
    const PotentialRegionSet& potentialRegions() const { return potential_; }
    mrpt::system::CTimeLogger& profiler() { return profiler_.get(); }

private:
    /** Drops scans whose passive block vanished and scans older than max_age_s. */
    void dropLostAndOld(hymm::ekf::EkfSlam& ekf, double time, AddReport& rep);
    void dropFront(hymm::ekf::EkfSlam& ekf);
    long nextPassiveId(const hymm::ekf::EkfSlam& ekf);
    void releaseUnusedPotentialRegions();
    /** Step 2 of addScan(): the returns of `z` that wait in the store, into `scan`. */
    void selectReturns(
        const hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition,
        const std::vector<Eigen::Vector2d>& z, const Eigen::Vector3d& sensor_on_vehicle,
        const std::vector<long>* tags, StoredScan& scan, AddReport& rep);

    const Options options_;
    std::deque<StoredScan> scans_;  //!< oldest first
    size_t num_points_ = 0;
    PotentialRegionSet potential_;
    long next_scan_id_ = 0;
    long next_passive_id_;
    double last_time_ = -1e300;
    core::LazyTimeLogger profiler_;
};

}  // namespace hymm::uif
