/**
 * @file DelayedDenseStore_bench.cpp
 * @brief Per-frame cost of the delayed dense store (thesis Sec. 3.7.3) against the number
 *        of stored returns and against the number of landmarks.
 *
 * One "frame" = DelayedDenseStore::fuse (every stored return is looked up; no region
 * covers them, so nothing leaves) + addScan of a 200-return scan, with the scan budget
 * fixed so the oldest scan (and its passive EKF block) is evicted: a steady state with
 * a constant number of stored returns. The filter holds n landmarks on a 10 m lattice
 * around the vehicle with a SLAM-like correlated covariance; the partition has no region.
 *
 * BM_EkfUpdateWithStore measures what the passive blocks add to the EKF's own update
 * (4 landmark observations), the O(3 S n_a m) term of DelayedDenseStore.h, against the
 * number of stored scans S.
 */
#include <hymm/core/RangeBearingModel.h>
#include <hymm/uif/DelayedDenseStore.h>
#include <mrpt/poses/CPose3D.h>

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>

namespace
{
using hymm::uif::DelayedDenseStore;

constexpr int kReturnsPerScan = 200;
const Eigen::Vector3d kSensor(0.3, 0.0, 0.0);
const Eigen::Matrix2d kR = Eigen::Vector2d(1e-4, 1e-5).asDiagonal();

/** n landmarks on a square 10 m lattice centred on the vehicle (a little jitter so no
 *  four are cocircular), all sharing a common error like a SLAM map. */
std::unique_ptr<hymm::ekf::EkfSlam> makeFilter(int n)
{
    auto ekf = std::make_unique<hymm::ekf::EkfSlam>(hymm::ekf::EkfSlam::Options());
    const int side = static_cast<int>(std::ceil(std::sqrt(n)));
    const Eigen::Index dim = 3 + 2 * n;
    Eigen::VectorXd x(dim);
    x.head<3>() << 1.0, 0.5, 0.2;
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(dim, 3);
    G.topLeftCorner<3, 3>() = Eigen::Vector3d(0.3, 0.3, 0.02).asDiagonal();
    std::vector<std::pair<long, int>> blocks;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> j(-1.0, 1.0);
    for (int i = 0; i < n; ++i)
    {
        const Eigen::Index o = 3 + 2 * i;
        x.segment<2>(o) << 10.0 * (i % side - side / 2) + j(rng), 10.0 * (i / side - side / 2) + j(rng);
        G.block<2, 2>(o, 0) = 0.3 * Eigen::Matrix2d::Identity();
        blocks.emplace_back(i, 2);
    }
    Eigen::MatrixXd P = G * G.transpose();
    P.diagonal().array() += 0.01;
    ekf->setActiveState(x, P, blocks);
    return ekf;
}

std::vector<Eigen::Vector2d> scanReturns(std::mt19937& rng)
{
    std::uniform_real_distribution<double> r(2.0, 12.0), b(-M_PI, M_PI);
    std::vector<Eigen::Vector2d> z;
    for (int i = 0; i < kReturnsPerScan; ++i) z.emplace_back(r(rng), b(rng));
    return z;
}

struct Setup
{
    std::unique_ptr<hymm::ekf::EkfSlam> ekf;
    hymm::ltr::RegionPartition partition{hymm::ltr::RegionPartition::Options()};
    std::unique_ptr<DelayedDenseStore> store;
    std::mt19937 rng{7};
    double t = 0;

    Setup(int landmarks, int stored_scans)
    {
        ekf = makeFilter(landmarks);
        DelayedDenseStore::Options o;
        o.enabled = true;
        o.max_stored_scans = static_cast<size_t>(stored_scans);
        o.max_stored_points = static_cast<size_t>(stored_scans) * kReturnsPerScan;
        store = std::make_unique<DelayedDenseStore>(o);
        for (int s = 0; s < stored_scans; ++s) frame();
    }
    void frame()
    {
        t += 0.1;
        store->fuse(*ekf, partition, [](long, const hymm::dense::RegionScan&) {});
        store->addScan(*ekf, partition, scanReturns(rng), kR, kSensor, t);
    }
};

void BM_StoreFrame_vsStoredReturns(benchmark::State& state)
{
    Setup s(50, static_cast<int>(state.range(0)));
    for (auto _ : state) s.frame();
    state.counters["stored_returns"] = static_cast<double>(s.store->numStoredPoints());
    state.counters["landmarks"] = 50;
}
BENCHMARK(BM_StoreFrame_vsStoredReturns)->Arg(5)->Arg(20)->Arg(80)->Unit(benchmark::kMicrosecond);

void BM_StoreFrame_vsLandmarks(benchmark::State& state)
{
    Setup s(static_cast<int>(state.range(0)), 10);
    for (auto _ : state) s.frame();
    state.counters["stored_returns"] = static_cast<double>(s.store->numStoredPoints());
    state.counters["landmarks"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_StoreFrame_vsLandmarks)->Arg(25)->Arg(100)->Arg(400)->Unit(benchmark::kMicrosecond);

void BM_EkfUpdateWithStore(benchmark::State& state)
{
    const int scans = static_cast<int>(state.range(0));
    const int landmarks = static_cast<int>(state.range(1));
    Setup s(landmarks, std::max(scans, 1));
    if (scans == 0) s.store->clear(*s.ekf);
    std::vector<hymm::ekf::RangeBearingObs> obs;
    for (long id = 0; id < 4; ++id)
    {
        hymm::ekf::RangeBearingObs o;
        o.z = hymm::core::observeRangeBearing(s.ekf->vehiclePose(), kSensor, s.ekf->landmarkMean(id));
        o.R = Eigen::Vector2d(0.01, 1e-4).asDiagonal();
        o.id = id;
        obs.push_back(o);
    }
    const mrpt::poses::CPose3D sensor(kSensor.x(), kSensor.y(), 0, kSensor.z(), 0, 0);
    for (auto _ : state)
    {
        state.PauseTiming();
        hymm::ekf::EkfSlam copy(*s.ekf);  // every iteration updates the same prior
        state.ResumeTiming();
        benchmark::DoNotOptimize(copy.updateRangeBearing(obs, sensor));
    }
    state.counters["passive_blocks"] = static_cast<double>(s.ekf->passive().numBlocks());
}
BENCHMARK(BM_EkfUpdateWithStore)
    ->Args({0, 100})
    ->Args({10, 100})
    ->Args({40, 100})
    ->Args({0, 400})
    ->Args({10, 400})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
