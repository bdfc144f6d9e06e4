/**
 * @file scan_matchers_bench.cpp
 * @brief Time of one alignment per matcher: a template of about 100 points against a
 *        361-beam scan (thesis Table 5.1 laser), started 0.1 m / 1 deg from the truth;
 *        and the two searches the real-data runs spend their time in: the scan
 *        odometry's correlative alignment of a whole scan, and a wide search.
 */
#include <benchmark/benchmark.h>
#include <hymm/scanslam/ScanMatcher.h>
#include <hymm/scanslam/ScanOdometry.h>
#include <hymm/scanslam/WideSearch.h>

#include "scan_pairs.h"

using namespace hymm::scanslam;

namespace
{
/** A fixed pair whose template has about 100 points. */
const hymm::bench::ScanPair& pair100()
{
    static const hymm::bench::ScanPair pair = [] {
        mrpt::random::CRandomGenerator rng(42);
        for (uint32_t s = 1;; ++s)
        {
            auto p = hymm::bench::randomPair(rng, s, 90);
            if (p && p->tpl.sog.size() >= 90 && p->tpl.sog.size() <= 120) return *p;
        }
    }();
    return pair;
}

void alignOnce(benchmark::State& state, const char* kind)
{
    const auto& p = pair100();
    const auto m = makeMatcher(kind);
    const Vec3 z0 = p.truth + Vec3(0.07, -0.07, M_PI / 180);
    size_t ok = 0;
    for (auto _ : state)
    {
        const AlignResult r = m->align(p.tpl.sog, p.scan, z0);
        ok += r.ok;
        benchmark::DoNotOptimize(r.z.data());
    }
    state.counters["template_pts"] = static_cast<double>(p.tpl.sog.size());
    state.counters["scan_pts"] = static_cast<double>(p.scan.size());
    state.counters["ok_fraction"] = static_cast<double>(ok) / static_cast<double>(state.iterations());
}

/** The scan odometry's matcher (`ScanOdometry::odometryMatcher`, correlative, 0.1 m grid):
 *  the scan seen from a pose 0.5 m / 3 deg on aligned to itself, from 0.1 m / 1 deg off. */
void scanOdometryAlign(benchmark::State& state)
{
    const auto& p = pair100();
    const auto m = hymm::scanslam::ScanOdometry::odometryMatcher("correlative", nullptr);
    const Vec3 motion(0.5, 0.05, 3 * M_PI / 180);
    PointSet previous;
    for (size_t k = 0; k < p.scan.size(); ++k)
        previous.add(transformPoint(inverse(motion), p.scan.points[k]), p.scan.covs[k]);
    const Vec3 z0 = motion + Vec3(0.07, -0.07, M_PI / 180);
    size_t ok = 0;
    for (auto _ : state)
    {
        const AlignResult r = m->align(previous, p.scan, z0);
        ok += r.ok;
        benchmark::DoNotOptimize(r.z.data());
    }
    state.counters["points"] = static_cast<double>(p.scan.size());
    state.counters["ok_fraction"] = static_cast<double>(ok) / static_cast<double>(state.iterations());
}

/** A wide search (`wideSearch`, default options) of the template from 1.5 m / 8 deg off,
 *  over +-3 m and +-15 deg: what a re-observation after drift costs. */
void wideSearchOnce(benchmark::State& state)
{
    const auto& p = pair100();
    const Vec3 z0 = p.truth + Vec3(1.5, -1.0, 8 * M_PI / 180);
    const Vec3 half(3, 3, 15 * M_PI / 180);
    size_t ok = 0;
    for (auto _ : state)
    {
        const auto r = hymm::scanslam::wideSearch(p.tpl.sog, p.scan, z0, half, {});
        ok += r.ok && (r.z.head<2>() - p.truth.head<2>()).norm() < 0.3;
        benchmark::DoNotOptimize(r.z.data());
    }
    state.counters["ok_near_truth"] = static_cast<double>(ok) / static_cast<double>(state.iterations());
}
}  // namespace

BENCHMARK(scanOdometryAlign)->Unit(benchmark::kMillisecond);
BENCHMARK(wideSearchOnce)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(alignOnce, sog, "sog")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(alignOnce, icp, "icp")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(alignOnce, correlative, "correlative")->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
