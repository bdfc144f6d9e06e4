// Cost of the motion-layer differencing (thesis Sec. 6.3) per call against map size.
// A lattice map of N regions (lattice_map.h), every region's occupancy filled; the
// "vehicle" drives a 4 m circle around the map's centre at 10 Hz and each call steps the
// detector with the regions within 14 m of it: the same ~50 regions at every N from 100
// to 8000 (the in_view counter shows it). The lists of regions in view are computed
// before the timed calls, so only MotionDetector's own work is timed.
//
// BM_MotionStep: fast differencing (1 s) of the regions in view, slow differencing (here
// 20 s, so that several periods fit in the timed calls) amortised through the due queue.
// The time per call should not grow with N.
//
// BM_MotionStepRemoval: the same (fast layer), but the detector first holds state for all
// N regions (one call with every region in view, the case of a long run), and every call
// also removes a region as the pipeline does after the partition dropped some: by id
// (removeRegions, walk 0: what DenseSlam calls; should not grow with N) or by walking every
// region held (removeStaleRegions, walk 1; grows with N). view_m: the view's radius.
//
// BM_MotionStepAllInView: every region of the map in view at every call (fast layer):
// the work per call is proportional to N, so is the time; reported per region.
//
// BM_MotionStepTiles: BM_MotionStep on a map that also keeps fallback tiles (about one
// per region); each call finds the tiles in view (HybridMetricMap::fallbackTilesInBox,
// timed: SlamMotionHook calls it every step) and differences them with the regions. The
// time per call should not grow with N.
#include "lattice_map.h"

#include <benchmark/benchmark.h>
#include <hymm/dynamic/MotionDetector.h>

namespace
{
using namespace hymm::dynamic::bench;

hymm::dynamic::MotionDetector::Options benchOptions()
{
    hymm::dynamic::MotionDetector::Options o;
    o.slow_period_s = 20.0;
    return o;
}

void setCounters(benchmark::State& state, const LatticeMap& m, size_t calls, size_t in_view, size_t fast,
                 size_t slow)
{
    const double c = static_cast<double>(calls);
    state.counters["regions"] = static_cast<double>(m.partition.size());
    state.counters["in_view"] = static_cast<double>(in_view) / c;
    state.counters["fast_per_call"] = static_cast<double>(fast) / c;
    state.counters["slow_per_call"] = static_cast<double>(slow) / c;
}

void BM_MotionStep(benchmark::State& state)
{
    LatticeMap m(static_cast<size_t>(state.range(0)));
    hymm::dynamic::MotionDetector det(benchOptions());
    const auto views = m.viewSchedule(0.0, 0.1, static_cast<size_t>(state.max_iterations));
    size_t fast = 0, slow = 0, in_view = 0, calls = 0;
    for (auto _ : state)
    {
        const auto& ids = views[calls];
        const auto r = det.step(m.map, ids, 0.1 * static_cast<double>(calls));
        fast += r.fast_differenced;
        slow += r.slow_differenced;
        in_view += ids.size();
        ++calls;
    }
    setCounters(state, m, calls, in_view, fast, slow);
}

void BM_MotionStepTiles(benchmark::State& state)
{
    LatticeMap m(static_cast<size_t>(state.range(0)), true);
    hymm::dynamic::MotionDetector det(benchOptions());
    const auto views = m.viewSchedule(0.0, 0.1, static_cast<size_t>(state.max_iterations));
    const V2 r(14.0, 14.0);
    size_t fast = 0, slow = 0, in_view = 0, tiles = 0, calls = 0;
    for (auto _ : state)
    {
        const double t = 0.1 * static_cast<double>(calls);
        const V2 v = m.vehicle(t);
        const auto tiles_in_view = m.map.fallbackTilesInBox(m.partition, v - r, v + r);
        const auto rep = det.step(m.map, views[calls], tiles_in_view, t);
        fast += rep.fast_differenced;
        slow += rep.slow_differenced;
        in_view += views[calls].size();
        tiles += tiles_in_view.size();
        ++calls;
    }
    setCounters(state, m, calls, in_view, fast, slow);
    state.counters["tiles"] = static_cast<double>(m.map.fallbackTiles());
    state.counters["tiles_in_view"] = static_cast<double>(tiles) / static_cast<double>(calls);
}

void BM_MotionStepRemoval(benchmark::State& state)
{
    LatticeMap m(static_cast<size_t>(state.range(0)));
    const bool walk = state.range(1) != 0;
    const double view_m = static_cast<double>(state.range(2));
    // The slow differencing is BM_MotionStep's subject: here its period is longer than
    // the timed calls, so that the N slow references taken below (all regions leave the
    // view at once) do not put a backlog of N due entries into the timed calls.
    auto o = benchOptions();
    o.slow_period_s = 1000.0;
    hymm::dynamic::MotionDetector det(o);
    det.step(m.map, m.partition.regionIds(), 0.0);  // state for every region
    det.step(m.map, m.inView(0.1, view_m), 0.1);    // their slow references
    const auto views = m.viewSchedule(0.2, 0.1, static_cast<size_t>(state.max_iterations), view_m);
    size_t held = 0, calls = 0, fast = 0, in_view = 0;
    for (auto _ : state)
    {
        const auto& ids = views[calls];
        fast += det.step(m.map, ids, 0.2 + 0.1 * static_cast<double>(calls)).fast_differenced;
        in_view += ids.size();
        // One region in view leaves the detector (the map keeps it, so the next call in
        // view brings it back: the number of regions held stays about N).
        if (walk)
            det.removeStaleRegions(m.map);  // walks all N; removes none here
        else
            det.removeRegions({ids[calls % ids.size()]});
        held += det.size();
        ++calls;
    }
    setCounters(state, m, calls, in_view, fast, 0);
    state.counters["held"] = static_cast<double>(held) / static_cast<double>(calls);
}

void BM_MotionStepAllInView(benchmark::State& state)
{
    LatticeMap m(static_cast<size_t>(state.range(0)));
    auto o = benchOptions();
    o.enable_slow = false;  // no region ever leaves the view
    hymm::dynamic::MotionDetector det(o);
    const auto ids = m.partition.regionIds();
    det.step(m.map, ids, 0.0);  // first snapshots, untimed
    size_t fast = 0, calls = 0;
    for (auto _ : state)
    {
        fast += det.step(m.map, ids, 0.1 * static_cast<double>(calls + 1)).fast_differenced;
        ++calls;
    }
    setCounters(state, m, calls, ids.size() * calls, fast, 0);
}

/** Maps of 100 to 8000 regions, 3000 calls each. */
void overMapSizes(benchmark::internal::Benchmark* b)
{
    b->ArgName("regions")->Arg(100)->Arg(500)->Arg(2000)->Arg(8000)->Iterations(3000)->Unit(benchmark::kMicrosecond);
}
BENCHMARK(BM_MotionStep)->Apply(overMapSizes);
BENCHMARK(BM_MotionStepTiles)->Apply(overMapSizes);
// view_m 14: ~50 regions in view at every N; 32: ~260, for N >= 2000 only (the disc of
// 36 m the view reaches needs ~330 regions), near the ~340 of the 25 m box used before.
BENCHMARK(BM_MotionStepRemoval)
    ->ArgsProduct({{100, 500, 2000, 8000}, {0, 1}, {14}})
    ->Args({2000, 0, 32})
    ->Args({8000, 0, 32})
    ->ArgNames({"regions", "walk", "view_m"})
    ->Iterations(3000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MotionStepAllInView)
    ->ArgName("regions")
    ->Arg(500)
    ->Arg(2000)
    ->Arg(8000)
    ->Iterations(100)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
