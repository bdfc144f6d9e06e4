// Per-step cost of EkfSlam (odometry prediction + one batched range-bearing update)
// against map size. Context: MRPT's kf-slam needs about 1 s per step at ~1000
// landmarks with ~100 observations per step; the goal is >= 20x faster there.
//
// Counters:
//  - n: active state size; m: observations fused per step;
//  - update_GFLOPs: flop rate of the update stage ("ekf.3_update": P H^T gather, S,
//    Cholesky, W = P H^T L^-T, P -= W W^T), counted against the n^2 * 2m flops of the
//    symmetric rank-2m covariance update that dominates it (lower triangle only:
//    n^2/2 entries x 2m multiply-adds x 2 flops). Plain x86-64 builds (SSE2, no FMA) peak
//    near 4 flops/cycle per core, so this shows how close the update runs to the bound.
// Run: build/benchmarks/ekf_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <hymm/core/RangeBearingModel.h>
#include <hymm/ekf/EkfSlam.h>

#include <cmath>
#include <iostream>
#include <random>

namespace
{
using namespace hymm::ekf;

const mrpt::poses::CPose3D kSensor(0.5, 0.0, 0.0, 0.0, 0.0, 0.0);
const Eigen::Vector3d kSensorVec(0.5, 0.0, 0.0);

/** A filter holding `n_lm` point landmarks with a valid, fully correlated covariance:
 *  built by the filter itself (batched augmentation of known-id observations, then a
 *  few updates), so P is PSD by construction. */
EkfSlam buildFilter(int n_lm, bool profile, std::mt19937& rng,
                    LinearisationPoint jacobians = LinearisationPoint::Current)
{
    EkfSlam::Options o;
    o.enable_profiler = profile;
    o.jacobians = jacobians;
    o.prune_tentative = false;
    EkfSlam f(o);
    f.reset(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, 0.01, 1e-4).asDiagonal());
    std::uniform_real_distribution<double> r(3.0, 80.0), a(-M_PI, M_PI);
    std::vector<RangeBearingObs> batch;
    for (int k = 0; k < n_lm; ++k)
    {
        RangeBearingObs ob;
        ob.z << r(rng), a(rng);
        ob.R = Eigen::Vector2d(0.1, 0.01).cwiseAbs2().asDiagonal();
        ob.id = k;
        batch.push_back(ob);
        if (batch.size() == 200 || k + 1 == n_lm)
        {
            f.updateRangeBearing(batch, kSensor);
            batch.clear();
        }
    }
    return f;
}

/** m noisy observations of landmarks chosen at random (known ids or to associate). */
std::vector<RangeBearingObs> observe(const EkfSlam& f, int m, bool known, std::mt19937& rng)
{
    std::normal_distribution<double> g(0.0, 1.0);
    const std::vector<long> ids = f.landmarkIds();
    std::uniform_int_distribution<size_t> pick(0, ids.size() - 1);
    std::vector<RangeBearingObs> obs;
    std::vector<bool> used(ids.size(), false);
    while (static_cast<int>(obs.size()) < m)
    {
        const size_t k = pick(rng);
        if (used[k]) continue;
        used[k] = true;
        RangeBearingObs o;
        o.R = Eigen::Vector2d(0.1, 0.01).cwiseAbs2().asDiagonal();
        o.z = hymm::core::observeRangeBearing(f.vehiclePose(), kSensorVec, f.landmarkMean(ids[k]));
        o.z += Eigen::Vector2d(0.1 * g(rng), 0.01 * g(rng));
        o.id = known ? ids[k] : -1;
        obs.push_back(o);
    }
    return obs;
}

void runStep(benchmark::State& state, LinearisationPoint jacobians)
{
    const int n_lm = static_cast<int>(state.range(0));
    const int m = static_cast<int>(state.range(1));
    const bool known = state.range(2) != 0;
    std::mt19937 rng(42);
    EkfSlam f = buildFilter(n_lm, true, rng, jacobians);
    mrpt::math::CMatrixDouble33 C;
    C.asEigen() = Eigen::Vector3d(0.02, 0.02, 0.005).cwiseAbs2().asDiagonal();
    const mrpt::poses::CPosePDFGaussian inc(mrpt::poses::CPose2D(0.0, 0.0, 0.0), C);
    // Observation batches prepared outside the timed region.
    std::vector<std::vector<RangeBearingObs>> batches;
    for (int b = 0; b < 8; ++b) batches.push_back(observe(f, m, known, rng));
    size_t b = 0, associated = 0;
    for (auto _ : state)
    {
        f.predictOdometry(inc);
        const UpdateReport rep = f.updateRangeBearing(batches[b++ % batches.size()], kSensor);
        associated += rep.associated;
        benchmark::DoNotOptimize(f.cov().data());
    }
    // Building the filter only augments, so every "ekf.3_update" call is a timed step.
    const double t_update = f.profiler().getMeanTime("ekf.3_update");
    const double n = static_cast<double>(f.mean().size());
    const double mm = static_cast<double>(associated) / static_cast<double>(state.iterations());
    state.counters["n"] = n;
    state.counters["m"] = mm;
    state.counters["update_GFLOPs"] = n * n * 2.0 * mm / t_update * 1e-9;
    state.counters["update_ms"] = 1e3 * t_update;
    f.profiler().clear(true);  // no statistics dump from every benchmark run
    f.profiler().disable();
}

void BM_EkfStep(benchmark::State& state) { runStep(state, LinearisationPoint::Current); }

/** The same step with each linearisation ([EkfSlam] jacobians; fourth argument 0 current,
 *  1 first_estimates, 2 invariant): the invariant EKF's transform M widens the update's
 *  covariance product by two columns, O(n^2) beside its O(n^2 m). */
void BM_EkfStepJacobians(benchmark::State& state)
{
    static const LinearisationPoint kJ[] = {LinearisationPoint::Current, LinearisationPoint::FirstEstimates,
                                            LinearisationPoint::Invariant};
    runStep(state, kJ[state.range(3)]);
}
BENCHMARK(BM_EkfStepJacobians)
    ->ArgsProduct({{1000}, {5, 50}, {1}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.5);

void sizes(benchmark::internal::Benchmark* b)
{
    for (int n : {100, 250, 500, 1000, 2000})
        for (int m : {50, 100}) b->Args({n, m, 1});
    b->Args({1000, 100, 0});  // NN association instead of known ids
    b->Args({2000, 100, 0});
}
BENCHMARK(BM_EkfStep)->Apply(sizes)->Unit(benchmark::kMillisecond)->MinTime(0.5);

}  // namespace

int main(int argc, char** argv)
{
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();

    // Profile of a few steps at 1000 landmarks x 100 observations (NN association).
    std::mt19937 rng(7);
    EkfSlam f = buildFilter(1000, true, rng);
    const mrpt::poses::CPosePDFGaussian inc(mrpt::poses::CPose2D(0.0, 0.0, 0.0));
    for (int s = 0; s < 5; ++s)
    {
        const auto obs = observe(f, 100, false, rng);
        f.predictOdometry(inc);
        f.updateRangeBearing(obs, kSensor);
    }
    std::cout << f.profiler().getStatsAsText();
    f.profiler().clear(true);
    f.profiler().disable();
    return 0;
}
