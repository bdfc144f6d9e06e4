// Cost of the motion-layer differencing (thesis Sec. 6.3) per call against map size.
// A lattice map of N regions, every region's occupancy filled; the "vehicle" drives a
// circle through it at 10 Hz, and each call steps the detector with the regions in a
// 25 m box around it: fast differencing (1 s) of the regions in view only, slow
// differencing (here 20 s, so that several periods fit in the timed calls) amortised
// through the due queue. The time per call should not grow with N.
//
// BM_MotionStepRemoval: the same (fast layer), but the detector first holds state for all
// N regions (one call with every region in view), and every call also removes regions as the
// pipeline does after the partition dropped some: by id (removeRegions, mode 0) or by
// walking every region held (removeStaleRegions, mode 1). Mode 0 is what DenseSlam
// calls; its time per call should not grow with N, mode 1's does.
#include "synthetic_partition.h"

#include <benchmark/benchmark.h>
#include <hymm/dense/HybridMetricMap.h>
#include <hymm/dynamic/MotionDetector.h>

#include <cmath>
#include <memory>

namespace
{
using namespace hymm::dense::synthetic;
using V2 = Eigen::Vector2d;
constexpr double kSpacing = 5.0;

hymm::dense::ScanPoints ringScan()
{
    hymm::dense::ScanPoints s;
    for (int k = 0; k < 181; ++k)
    {
        const double a = -M_PI / 2 + M_PI * k / 180.0;
        s.points.emplace_back(6.0 * std::cos(a), 6.0 * std::sin(a));
    }
    return s;
}

/** The lattice map of about `regions` regions, every region's occupancy filled. */
struct LatticeMap
{
    int side;
    Lattice lattice;
    IndependentLandmarksView view;
    hymm::ltr::RegionPartition partition{permissivePartitionOptions()};
    V2 centre;
    hymm::dense::HybridMetricMap map;

    static hymm::dense::HybridMetricMap::Options mapOptions()
    {
        hymm::dense::HybridMetricMap::Options mo;
        mo.enable_points = false;
        mo.occupancy.cell_size_m = 0.2;
        return mo;
    }
    explicit LatticeMap(size_t regions)
        : side(static_cast<int>(std::ceil(std::sqrt(static_cast<double>(regions) / 2.0))) + 2),
          lattice{side, side, kSpacing, V2(0, 0)},
          view(lattice.landmarks()),
          centre(0.5 * kSpacing * (side - 1) * V2(1, 1)),
          map(mapOptions())
    {
        addRegions(partition, view, lattice.triangles(centre), regions);
        const auto scan = ringScan();
        for (int i = 0; i < side; ++i)
            for (int j = 0; j < side; ++j)
                map.insertScan(scan, {kSpacing * (i + 0.5), kSpacing * (j + 0.5), 0.0}, partition);
    }
    /** Regions in the 25 m box around the vehicle on its circle at time t. */
    std::vector<long> inView(double t) const
    {
        const double a = 0.05 * t;  // a lap every ~2 min
        const V2 v = centre + 12.0 * V2(std::cos(a), std::sin(a));
        return partition.regionsInBox(v - V2(25, 25), v + V2(25, 25));
    }
};

hymm::dynamic::MotionDetector::Options benchOptions()
{
    hymm::dynamic::MotionDetector::Options o;
    o.slow_period_s = 20.0;
    return o;
}

void BM_MotionStep(benchmark::State& state)
{
    LatticeMap m(static_cast<size_t>(state.range(0)));
    hymm::dynamic::MotionDetector det(benchOptions());
    double t = 0;
    size_t fast = 0, slow = 0, in_view = 0, calls = 0;
    for (auto _ : state)
    {
        const auto ids = m.inView(t);
        const auto r = det.step(m.map, ids, t);
        fast += r.fast_differenced;
        slow += r.slow_differenced;
        in_view += ids.size();
        ++calls;
        t += 0.1;
    }
    state.counters["regions"] = static_cast<double>(m.partition.size());
    state.counters["in_view"] = static_cast<double>(in_view) / static_cast<double>(calls);
    state.counters["fast_per_call"] = static_cast<double>(fast) / static_cast<double>(calls);
    state.counters["slow_per_call"] = static_cast<double>(slow) / static_cast<double>(calls);
}

void BM_MotionStepRemoval(benchmark::State& state)
{
    LatticeMap m(static_cast<size_t>(state.range(0)));
    const bool walk = state.range(1) != 0;
    // The slow differencing is BM_MotionStep's subject: here its period is longer than
    // the timed calls, so that the N slow references taken below (all regions leave the
    // view at once) do not put a backlog of N due entries into the timed calls.
    auto o = benchOptions();
    o.slow_period_s = 1000.0;
    hymm::dynamic::MotionDetector det(o);
    det.step(m.map, m.partition.regionIds(), 0.0);  // state for every region
    det.step(m.map, m.inView(0.1), 0.1);            // their slow references
    double t = 0.2;
    size_t held = 0, calls = 0, fast = 0, in_view = 0;
    for (auto _ : state)
    {
        const auto ids = m.inView(t);
        fast += det.step(m.map, ids, t).fast_differenced;
        in_view += ids.size();
        // One region in view leaves the detector (the map keeps it, so the next call in
        // view brings it back: the number of regions held stays about N).
        const std::vector<long> gone{ids[calls % ids.size()]};
        if (walk)
            det.removeStaleRegions(m.map);  // walks all N; removes none here
        else
            det.removeRegions(gone);
        held += det.size();
        ++calls;
        t += 0.1;
    }
    state.counters["regions"] = static_cast<double>(m.partition.size());
    state.counters["held"] = static_cast<double>(held) / static_cast<double>(calls);
    state.counters["in_view"] = static_cast<double>(in_view) / static_cast<double>(calls);
    state.counters["fast_per_call"] = static_cast<double>(fast) / static_cast<double>(calls);
}

BENCHMARK(BM_MotionStep)
    ->Arg(100)
    ->Arg(500)
    ->Arg(2000)
    ->Iterations(3000)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MotionStepRemoval)
    ->ArgsProduct({{500, 2000, 8000}, {0, 1}})
    ->ArgNames({"regions", "walk"})
    ->Iterations(2000)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
