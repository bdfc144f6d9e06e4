/**
 * @file DenseStep_bench.cpp
 * @brief The thesis claim that the dense layers add O(1) per step, measured on the
 *        pipeline's own dense step over a real EkfSlam (docs/benchmarks.md, "Dense part
 *        per step (O(1) claim)").
 *
 * denseStep() below is the call sequence of DenseSlam::processDense for a frame with an
 * EKF update and one laser scan: stale-region check, partition refresh + growth, then
 * HybridMetricMap::insertScan of a 361-beam scan. Two modes:
 *  - full  ([LtrPartition] local_refresh = false): RegionPartition::update() re-reads
 *    every region, rebuilds its grid entries and scans every landmark id;
 *  - local (local_refresh = true): RegionPartition::updateNear() refreshes only the
 *    regions around the vehicle and takes the nearby landmarks from
 *    EkfCovarianceView::idsNear().
 *
 * World: the vehicle stands in a 3 x 3 lattice of landmarks (8 m spacing, 8 regions)
 * and scans a 14 m square room (361 beams over 180 deg) that lies inside those regions;
 * the partition there is saturated (growth is attempted every step and finds nothing
 * to add, as in an explored area). The rest of the map, N - 9 landmarks and R - 8
 * regions, is a second lattice 1 km away: it changes the size of the filter and of the
 * partition, not the work near the vehicle. The filter holds a full, correlated
 * covariance (landmark = vehicle position + rotated offset + independent noise).
 *
 * BM_DenseStep/N/R/mode: the dense step alone (the filter is not changed between
 * iterations). mode 2: local refresh with the fallback on ([HybridMetricMap]
 * fallback_max_distance_m = 25) and a 20 m room, so that part of the returns lie
 * beyond the local regions and go to fallback tiles; mode 3: the same with
 * fallback_reuse_m = 10. BM_EkfVsDense/N/R/m/mode/cell_cm: per iteration one EKF step
 * (odometry prediction + update with m known-id range-bearing observations) followed by
 * the dense step, occupancy cells of cell_cm centimetres; the counters report the
 * medians of the two parts and ratio = (ekf + dense) / ekf.
 * Run: build-bench/benchmarks/denseslam_bench  (see docs/benchmarks.md)
 */
#include "synthetic_partition.h"

#include <benchmark/benchmark.h>
#include <hymm/core/RangeBearingModel.h>
#include <hymm/dense/HybridMetricMap.h>
#include <hymm/denseslam/EkfCovarianceView.h>
#include <hymm/ekf/EkfSlam.h>
#include <hymm/ltr/RegionPartition.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <vector>

namespace
{
using hymm::dense::HybridMetricMap;
using hymm::dense::ScanPoints;
using hymm::dense::synthetic::Lattice;
using hymm::denseslam::EkfCovarianceView;
using hymm::ekf::EkfSlam;
using hymm::ltr::RegionPartition;
using V2 = Eigen::Vector2d;

constexpr double kSpacing = 8.0;
constexpr double kReuse = 10.0;  // [m] fallback_reuse_m of mode 3
constexpr int kLocalSide = 3;  // 9 landmarks, 8 regions around the vehicle
constexpr size_t kLocalRegions = 8;
const V2 kVehicle(4.5, 8.0);         // inside the local lattice, room inside its regions
const V2 kFarOrigin(1000.0, 0.0);    // the rest of the map
const mrpt::poses::CPose3D kSensor;  // range-bearing sensor at the vehicle origin

ScanPoints roomScan(double half_side = 7.0)
{
    ScanPoints s;
    for (int k = 0; k < 361; ++k)
    {
        const double a = -M_PI / 2 + M_PI * k / 360.0;
        const double r = half_side / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)));
        s.points.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    return s;
}

/** Landmark k of the far part in row-major order on rows of `ny`. */
V2 farPosition(size_t k, int ny)
{
    return kFarOrigin + kSpacing * V2(static_cast<double>(k / static_cast<size_t>(ny)),
                                      static_cast<double>(k % static_cast<size_t>(ny)));
}

struct World
{
    std::unique_ptr<EkfSlam> ekf;
    std::unique_ptr<RegionPartition> partition;
    std::unique_ptr<HybridMetricMap> map;
    size_t landmarks = 0;

    /** mode: 0 full refresh, 1 local, 2 local + fallback, 3 local + fallback with tile
     *  reuse (fallback_reuse_m = kReuse). */
    World(size_t n_landmarks, size_t n_regions, int mode, double cell_m = 0.1)
    {
        const bool local = mode != 0, fallback = mode >= 2;
        if (n_landmarks < 9 || n_regions < kLocalRegions)
            throw std::invalid_argument("World: too small");
        // --- landmarks: local 3x3 lattice, then the far block (ids 100000 + k) --------
        std::vector<std::pair<long, V2>> lms;
        const Lattice local_lattice{kLocalSide, kLocalSide, kSpacing, V2::Zero()};
        for (const auto& [id, p] : local_lattice.landmarks()) lms.emplace_back(id, p);
        const size_t n_far = n_landmarks - lms.size();
        const int ny = std::max(2, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n_far)))));
        for (size_t k = 0; k < n_far; ++k)
            lms.emplace_back(100000 + static_cast<long>(k), farPosition(k, ny));
        landmarks = lms.size();

        // --- a real filter with a full, correlated covariance ----------------------
        const Eigen::Index n = 3 + 2 * static_cast<Eigen::Index>(lms.size());
        Eigen::VectorXd x(n);
        x.head<3>() << kVehicle.x(), kVehicle.y(), 0.0;
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, 3);
        A.topLeftCorner<3, 3>().setIdentity();
        std::vector<std::pair<long, int>> blocks;
        for (size_t k = 0; k < lms.size(); ++k)
        {
            const Eigen::Index o = 3 + 2 * static_cast<Eigen::Index>(k);
            const V2 d = lms[k].second - kVehicle;
            x.segment<2>(o) = lms[k].second;
            A.block<2, 3>(o, 0) << 1, 0, -d.y(), 0, 1, d.x();
            blocks.emplace_back(lms[k].first, 2);
        }
        const Eigen::Matrix3d Pv = Eigen::Vector3d(0.5, 0.5, 0.002).cwiseAbs2().asDiagonal();
        Eigen::MatrixXd P = A * (Pv * A.transpose());
        P.diagonal().tail(n - 3).array() += 0.2 * 0.2;
        P = (0.5 * (P + P.transpose())).eval();
        EkfSlam::Options eo;
        eo.prune_tentative = false;
        ekf = std::make_unique<EkfSlam>(eo);
        ekf->setActiveState(x, P, blocks);

        // --- partition: the 8 local triangles, then R - 8 far ones -----------------
        RegionPartition::Options po = hymm::dense::synthetic::permissivePartitionOptions();
        po.local_refresh = local;
        partition = std::make_unique<RegionPartition>(po);
        const EkfCovarianceView view(*ekf);
        hymm::dense::synthetic::addRegions(*partition, view, local_lattice.triangles(kVehicle),
                                           kLocalRegions);
        const size_t far_regions = n_regions - kLocalRegions;
        size_t added = 0;
        const auto farId = [&](size_t i, size_t j) -> long {
            const size_t k = i * static_cast<size_t>(ny) + j;
            return k < n_far ? 100000 + static_cast<long>(k) : -1;
        };
        for (size_t i = 0; added < far_regions && i + 1 < n_far; ++i)
            for (size_t j = 0; added < far_regions && j + 1 < static_cast<size_t>(ny); ++j)
            {
                const long a = farId(i, j), b = farId(i + 1, j), c = farId(i, j + 1),
                           e = farId(i + 1, j + 1);
                if (a < 0 || b < 0 || c < 0 || e < 0) continue;
                for (const std::array<long, 3>& t : {std::array<long, 3>{a, b, c}, {b, e, c}})
                {
                    if (added == far_regions) break;
                    if (!partition->tryAddRegion(t, view, 0.0).accepted())
                        throw std::runtime_error("World: far region refused");
                    ++added;
                }
            }
        if (partition->size() != n_regions)
            throw std::runtime_error("World: not enough landmarks for the regions asked");

        HybridMetricMap::Options mo;
        mo.occupancy.cell_size_m = cell_m;
        mo.points.voxel_size_m = 0.02;  // bounds memory over many identical iterations
        mo.fallback_max_distance_m = fallback ? 25.0 : 0.0;
        mo.fallback_reuse_m = mode == 3 ? kReuse : 0.0;
        map = std::make_unique<HybridMetricMap>(mo);
    }
};

struct StepStats
{
    size_t created = 0, stale = 0, returns_stored = 0, regions_visited = 0, returns_fallback = 0;
};

/** DenseSlam::processDense for one frame with an EKF update and one scan. */
StepStats denseStep(World& w, const ScanPoints& scan, double t)
{
    StepStats st;
    const EkfCovarianceView view(*w.ekf);
    const auto& po = w.partition->options();
    const V2 vehicle_xy = w.ekf->vehiclePose().head<2>();
    const bool local = po.local_refresh && (vehicle_xy - w.ekf->predictedPose().head<2>()).norm() <=
                                               po.full_refresh_correction_m;
    const double reach = w.map->options().max_range_m;
    const auto stale = local ? w.partition->regionsWithMissingLandmarksNear(view, vehicle_xy, reach)
                             : w.partition->regionsWithMissingLandmarks(view);
    for (const long id : stale) w.partition->removeRegion(id);
    if (!stale.empty()) w.map->removeRegions(stale);  // as DenseSlam::updateRegions
    st.stale = stale.size();
    st.created = (local ? w.partition->updateNear(view, t, reach) : w.partition->update(view, t)).size();

    const Eigen::Vector3d v = w.ekf->vehiclePose();
    const auto ins = w.map->insertScan(scan, mrpt::math::TPose2D(v[0], v[1], v[2]), *w.partition);
    st.returns_stored = ins.returns_stored;
    st.returns_fallback = ins.returns_fallback;
    st.regions_visited = ins.regions_visited;
    return st;
}

/** Steady state or an error: the step must neither grow nor shrink the partition, and
 *  must store the scan (otherwise the benchmark measures nothing). */
bool checkStep(benchmark::State& state, const StepStats& st)
{
    if (st.returns_stored == 0 || st.created != 0 || st.stale != 0)
    {
        state.SkipWithError("dense step not in steady state (stored / created / stale)");
        return false;
    }
    return true;
}

/** Args: landmarks, regions, local (0/1). */
void BM_DenseStep(benchmark::State& state)
{
    const int mode = static_cast<int>(state.range(2));
    World w(static_cast<size_t>(state.range(0)), static_cast<size_t>(state.range(1)), mode);
    const ScanPoints scan = roomScan(mode >= 2 ? 10.0 : 7.0);
    StepStats st = denseStep(w, scan, 0.0);  // warm-up: allocates the local maps
    if (!checkStep(state, st)) return;
    double t = 1.0;
    for (auto _ : state)
    {
        st = denseStep(w, scan, t);
        t += 1.0;
        benchmark::DoNotOptimize(st.returns_stored);
    }
    if (!checkStep(state, st)) return;
    if (mode >= 2 && st.returns_fallback == 0)
    {
        state.SkipWithError("fallback mode: no return went to the fallback");
        return;
    }
    state.counters["returns_fallback"] = static_cast<double>(st.returns_fallback);
    state.counters["landmarks"] = static_cast<double>(w.landmarks);
    state.counters["regions"] = static_cast<double>(w.partition->size());
    state.counters["returns_stored"] = static_cast<double>(st.returns_stored);
    state.counters["regions_visited"] = static_cast<double>(st.regions_visited);
    state.counters["fallback_tiles"] = static_cast<double>(w.map->fallbackTiles());
}

void denseArgs(benchmark::internal::Benchmark* b)
{
    for (int mode : {0, 1, 2, 3})
    {
        for (int n : {100, 250, 500, 1000, 2000}) b->Args({n, 100, mode});  // landmarks
        for (int r : {10, 500, 1000, 2000}) b->Args({2000, r, mode});       // regions
        b->Args({100, 10, mode});
    }
}
BENCHMARK(BM_DenseStep)
    ->Apply(denseArgs)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true)
    ->Unit(benchmark::kMicrosecond);

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    const size_t h = v.size() / 2;
    return v.size() % 2 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}

/** Args: landmarks, regions, observations per step, refresh (0 full, 1 local, 2 local
 *  with the dense fallback at 25 m and a 20 m room: more than half of every scan goes to
 *  fallback tiles, as BM_DenseStep mode 2). */
void BM_EkfVsDense(benchmark::State& state)
{
    const int mode = static_cast<int>(state.range(3));
    const bool fallback = mode >= 2;
    World w(static_cast<size_t>(state.range(0)), static_cast<size_t>(state.range(1)), mode,
            0.01 * static_cast<double>(state.range(4)));
    const int m = static_cast<int>(state.range(2));
    const ScanPoints scan = roomScan(fallback ? 10.0 : 7.0);
    std::mt19937 rng(42);
    // Observations: m landmarks at random, predicted from the current estimate plus noise;
    // the prediction is a standing vehicle with odometry noise.
    const std::vector<long> ids = w.ekf->landmarkIds();
    std::uniform_int_distribution<size_t> pick(0, ids.size() - 1);
    std::normal_distribution<double> g(0.0, 1.0);
    mrpt::math::CMatrixDouble33 C;
    C.asEigen() = Eigen::Vector3d(0.02, 0.02, 0.002).cwiseAbs2().asDiagonal();
    const mrpt::poses::CPosePDFGaussian inc(mrpt::poses::CPose2D(0.0, 0.0, 0.0), C);
    std::vector<std::vector<hymm::ekf::RangeBearingObs>> batches;
    for (int b = 0; b < 8; ++b)
    {
        std::vector<hymm::ekf::RangeBearingObs> obs;
        std::vector<long> chosen;
        while (static_cast<int>(obs.size()) < m)
        {
            const long id = ids[pick(rng)];
            if (std::find(chosen.begin(), chosen.end(), id) != chosen.end()) continue;
            chosen.push_back(id);
            hymm::ekf::RangeBearingObs o;
            o.R = Eigen::Vector2d(0.1, 0.01).cwiseAbs2().asDiagonal();
            o.z = hymm::core::observeRangeBearing(w.ekf->vehiclePose(), Eigen::Vector3d::Zero(),
                                                  w.ekf->landmarkMean(id)) +
                  Eigen::Vector2d(0.1 * g(rng), 0.01 * g(rng));
            o.id = id;
            obs.push_back(o);
        }
        batches.push_back(std::move(obs));
    }
    if (!checkStep(state, denseStep(w, scan, 0.0))) return;

    using Clock = std::chrono::steady_clock;
    std::vector<double> ekf_us, dense_us;
    size_t b = 0, associated = 0;
    StepStats st;
    double t = 1.0;
    for (auto _ : state)
    {
        const auto t0 = Clock::now();
        w.ekf->predictOdometry(inc);
        associated += w.ekf->updateRangeBearing(batches[b++ % batches.size()], kSensor).associated;
        benchmark::DoNotOptimize(w.ekf->cov().data());
        const auto t1 = Clock::now();
        st = denseStep(w, scan, t);
        t += 1.0;
        benchmark::DoNotOptimize(st.returns_stored);
        const auto t2 = Clock::now();
        ekf_us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
        dense_us.push_back(std::chrono::duration<double, std::micro>(t2 - t1).count());
        state.SetIterationTime(std::chrono::duration<double>(t2 - t0).count());
    }
    if (!checkStep(state, st)) return;
    if (fallback && st.returns_fallback == 0)
    {
        state.SkipWithError("fallback mode: no return went to the fallback");
        return;
    }
    if (associated != static_cast<size_t>(m) * ekf_us.size())
    {
        state.SkipWithError("EKF did not use every observation");
        return;
    }
    const double e = median(ekf_us), d = median(dense_us);
    state.counters["ekf_us"] = e;
    state.counters["dense_us"] = d;
    state.counters["ratio"] = (e + d) / e;
    state.counters["landmarks"] = static_cast<double>(w.landmarks);
    state.counters["regions"] = static_cast<double>(w.partition->size());
    state.counters["m"] = m;
    state.counters["returns_fallback"] = static_cast<double>(st.returns_fallback);
    state.counters["fallback_tiles"] = static_cast<double>(w.map->fallbackTiles());
}
void ekfVsDenseArgs(benchmark::internal::Benchmark* b)
{
    for (int cell_cm : {10, 20})  // 0.1 m as before; 0.2 m as every shipped config
    {
        b->Args({1000, 1000, 15, 0, cell_cm});
        for (int mode : {1, 2, 3})
            for (int m : {10, 15, 20}) b->Args({1000, 1000, m, mode, cell_cm});
    }
}
BENCHMARK(BM_EkfVsDense)
    ->Apply(ekfVsDenseArgs)
    ->Iterations(60)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
