// Cost of adding and removing landmarks in EkfSlam (augmentation, Eq. 2.53, and the
// marginalisation that pruning does), apart from the update.
//
//  - BM_EkfAugmentAt/n/k: one update step that only creates k point landmarks (known
//    new ids) in a filter holding n landmarks; the k are removed again outside the timed
//    region, so every iteration starts at the same size. Eq. 2.53 itself is O(n k).
//  - BM_EkfRemoveRecent/n/k: removing the k most recent landmarks (what pruning of
//    tentative landmarks does) from a filter holding n landmarks; adding them back is not
//    timed.
//  - BM_EkfGrow/N/k: a whole growing map, N landmarks added k per step from an empty
//    filter (the pattern of a run that explores: every step adds a few landmarks). Its
//    total is what a run spends in augmentation.
//
// Run: build/benchmarks/ekf_augment_bench --benchmark_repetitions=5
//          --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <hymm/ekf/EkfSlam.h>

#include <cmath>
#include <random>
#include <vector>

namespace
{
using namespace hymm::ekf;

const mrpt::poses::CPose3D kSensor(0.5, 0.0, 0.0, 0.0, 0.0, 0.0);

EkfSlam::Options options()
{
    EkfSlam::Options o;
    o.prune_tentative = false;  // the benchmark removes landmarks itself
    return o;
}

/** k observations of new landmarks with ids first_id, first_id + 1, ... */
std::vector<RangeBearingObs> newLandmarks(long first_id, int k, std::mt19937& rng)
{
    std::uniform_real_distribution<double> r(3.0, 80.0), a(-M_PI, M_PI);
    std::vector<RangeBearingObs> batch;
    for (int i = 0; i < k; ++i)
    {
        RangeBearingObs ob;
        ob.z << r(rng), a(rng);
        ob.R = Eigen::Vector2d(0.1, 0.01).cwiseAbs2().asDiagonal();
        ob.id = first_id + i;
        batch.push_back(ob);
    }
    return batch;
}

/** A filter with n landmarks and a fully correlated covariance (built by the filter). */
EkfSlam buildFilter(int n, std::mt19937& rng)
{
    EkfSlam f(options());
    f.reset(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, 0.01, 1e-4).asDiagonal());
    for (int k = 0; k < n; k += 200) f.updateRangeBearing(newLandmarks(k, std::min(200, n - k), rng), kSensor);
    return f;
}

void BM_EkfAugmentAt(benchmark::State& state)
{
    const int n = static_cast<int>(state.range(0)), k = static_cast<int>(state.range(1));
    std::mt19937 rng(42);
    EkfSlam f = buildFilter(n, rng);
    const auto batch = newLandmarks(n, k, rng);
    for (auto _ : state)
    {
        const UpdateReport rep = f.updateRangeBearing(batch, kSensor);
        benchmark::DoNotOptimize(rep.created);
        state.PauseTiming();
        for (int i = 0; i < k; ++i) f.removeLandmark(n + i);
        state.ResumeTiming();
    }
    state.counters["state"] = static_cast<double>(f.mean().size());
}

void BM_EkfRemoveRecent(benchmark::State& state)
{
    const int n = static_cast<int>(state.range(0)), k = static_cast<int>(state.range(1));
    std::mt19937 rng(42);
    EkfSlam f = buildFilter(n, rng);
    const auto batch = newLandmarks(n, k, rng);
    for (auto _ : state)
    {
        state.PauseTiming();
        f.updateRangeBearing(batch, kSensor);
        state.ResumeTiming();
        for (int i = 0; i < k; ++i) f.removeLandmark(n + i);
        benchmark::DoNotOptimize(f.mean().data());
    }
    state.counters["state"] = static_cast<double>(f.mean().size());
}

void BM_EkfGrow(benchmark::State& state)
{
    const int n = static_cast<int>(state.range(0)), k = static_cast<int>(state.range(1));
    std::mt19937 rng(42);
    std::vector<std::vector<RangeBearingObs>> batches;
    for (int i = 0; i < n; i += k) batches.push_back(newLandmarks(i, std::min(k, n - i), rng));
    for (auto _ : state)
    {
        EkfSlam f(options());
        f.reset(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, 0.01, 1e-4).asDiagonal());
        for (const auto& b : batches) f.updateRangeBearing(b, kSensor);
        benchmark::DoNotOptimize(f.mean().data());
    }
}

BENCHMARK(BM_EkfAugmentAt)->Args({1000, 8})->Args({2000, 8})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EkfRemoveRecent)->Args({1000, 8})->Args({2000, 8})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EkfGrow)->Args({1000, 8})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
