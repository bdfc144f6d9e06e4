// Cost of the motion-layer differencing (thesis Sec. 6.3) per call against map size.
// A lattice map of N regions, every region's occupancy filled; the "vehicle" drives a
// circle through it at 10 Hz, and each call steps the detector with the regions in a
// 25 m box around it: fast differencing (1 s) of the regions in view only, slow
// differencing (here 20 s, so that several periods fit in the timed calls) amortised
// through the due queue. The time per call should not grow with N.
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

void BM_MotionStep(benchmark::State& state)
{
    const auto regions = static_cast<size_t>(state.range(0));
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(regions) / 2.0))) + 2;
    Lattice lattice{side, side, kSpacing, V2(0, 0)};
    IndependentLandmarksView view(lattice.landmarks());
    hymm::ltr::RegionPartition partition(permissivePartitionOptions());
    const V2 centre = 0.5 * kSpacing * (side - 1) * V2(1, 1);
    addRegions(partition, view, lattice.triangles(centre), regions);
    hymm::dense::HybridMetricMap::Options mo;
    mo.enable_points = false;
    mo.occupancy.cell_size_m = 0.2;
    hymm::dense::HybridMetricMap map(mo);
    const auto scan = ringScan();
    for (int i = 0; i < side; ++i)
        for (int j = 0; j < side; ++j)
            map.insertScan(scan, {kSpacing * (i + 0.5), kSpacing * (j + 0.5), 0.0}, partition);
    hymm::dynamic::MotionDetector::Options o;
    o.slow_period_s = 20.0;
    hymm::dynamic::MotionDetector det(o);
    const double radius = 12.0;
    double t = 0;
    size_t fast = 0, slow = 0, in_view = 0, calls = 0;
    for (auto _ : state)
    {
        const double a = 0.05 * t;  // a lap every ~2 min
        const V2 v = centre + radius * V2(std::cos(a), std::sin(a));
        const auto ids = partition.regionsInBox(v - V2(25, 25), v + V2(25, 25));
        const auto r = det.step(map, ids, t);
        fast += r.fast_differenced;
        slow += r.slow_differenced;
        in_view += ids.size();
        ++calls;
        t += 0.1;
    }
    state.counters["regions"] = static_cast<double>(partition.size());
    state.counters["in_view"] = static_cast<double>(in_view) / static_cast<double>(calls);
    state.counters["fast_per_call"] = static_cast<double>(fast) / static_cast<double>(calls);
    state.counters["slow_per_call"] = static_cast<double>(slow) / static_cast<double>(calls);
}
BENCHMARK(BM_MotionStep)
    ->Arg(100)
    ->Arg(500)
    ->Arg(2000)
    ->Iterations(3000)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
