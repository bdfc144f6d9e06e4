// hymm::eval::alignSE2 against MRPT's mrpt::tfest::se2_l2 (the same closed-form
// least-squares rigid 2D fit) on n point pairs: a path of n poses on a 250 m loop
// around (offset, offset) with 0.5 m of noise, aligned onto its truth. The pairs are
// built outside the timed region; se2_l2 also needs them as a float TMatchingPairList,
// whose conversion is timed separately (BM_Se2L2WithConversion: what a call from
// HYMM's Eigen point lists costs).
//
// Run: build/benchmarks/se2_alignment_bench --benchmark_repetitions=5
//          --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <hymm/eval/se2_alignment.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/tfest/se2.h>

#include <cmath>
#include <random>
#include <vector>

namespace
{
struct Pairs
{
    std::vector<Eigen::Vector2d> src, dst;
    mrpt::tfest::TMatchingPairList list;
};

Pairs makePairs(size_t n, double offset)
{
    std::mt19937 rng(1);
    std::normal_distribution<double> noise(0.0, 0.5);
    Pairs p;
    const double c = std::cos(0.3), s = std::sin(0.3);
    for (size_t i = 0; i < n; ++i)
    {
        const double a = 2 * M_PI * i / n;
        const Eigen::Vector2d d(offset + 40 * std::cos(a), offset + 40 * std::sin(a));
        const Eigen::Vector2d e(c * d.x() - s * d.y() + 5 + noise(rng), s * d.x() + c * d.y() - 3 + noise(rng));
        p.src.push_back(e);
        p.dst.push_back(d);
    }
    for (size_t i = 0; i < n; ++i)
        p.list.emplace_back(mrpt::tfest::TMatchingPair(
            i, i, static_cast<float>(p.dst[i].x()), static_cast<float>(p.dst[i].y()), 0.f,
            static_cast<float>(p.src[i].x()), static_cast<float>(p.src[i].y()), 0.f));
    return p;
}

void BM_AlignSE2(benchmark::State& st)
{
    const auto p = makePairs(static_cast<size_t>(st.range(0)), 0.0);
    for (auto _ : st) benchmark::DoNotOptimize(hymm::eval::alignSE2(p.src, p.dst));
}

void BM_Se2L2(benchmark::State& st)
{
    const auto p = makePairs(static_cast<size_t>(st.range(0)), 0.0);
    mrpt::math::TPose2D out;
    for (auto _ : st)
    {
        benchmark::DoNotOptimize(mrpt::tfest::se2_l2(p.list, out));
        benchmark::DoNotOptimize(out);
    }
}

void BM_Se2L2WithConversion(benchmark::State& st)
{
    const auto p = makePairs(static_cast<size_t>(st.range(0)), 0.0);
    mrpt::math::TPose2D out;
    for (auto _ : st)
    {
        mrpt::tfest::TMatchingPairList list;
        list.reserve(p.src.size());
        for (size_t i = 0; i < p.src.size(); ++i)
            list.emplace_back(mrpt::tfest::TMatchingPair(
                i, i, static_cast<float>(p.dst[i].x()), static_cast<float>(p.dst[i].y()), 0.f,
                static_cast<float>(p.src[i].x()), static_cast<float>(p.src[i].y()), 0.f));
        benchmark::DoNotOptimize(mrpt::tfest::se2_l2(list, out));
        benchmark::DoNotOptimize(out);
    }
}
}  // namespace

BENCHMARK(BM_AlignSE2)->Arg(469)->Arg(6000);
BENCHMARK(BM_Se2L2)->Arg(469)->Arg(6000);
BENCHMARK(BM_Se2L2WithConversion)->Arg(469)->Arg(6000);
BENCHMARK_MAIN();
