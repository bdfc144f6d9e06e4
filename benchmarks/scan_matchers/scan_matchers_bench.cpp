/**
 * @file scan_matchers_bench.cpp
 * @brief Time of one alignment per matcher: a template of about 100 points against a
 *        361-beam scan (thesis Table 5.1 laser), started 0.1 m / 1 deg from the truth.
 */
#include <benchmark/benchmark.h>
#include <hymm/scanslam/ScanMatcher.h>

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
}  // namespace

BENCHMARK_CAPTURE(alignOnce, sog, "sog")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(alignOnce, icp, "icp")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(alignOnce, correlative, "correlative")->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
