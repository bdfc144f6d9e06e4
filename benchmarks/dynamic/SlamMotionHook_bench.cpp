// Cost of SlamMotionHook::afterFrame (thesis Sec. 6.3) against the number of landmarks
// in the filter. The lattice map of 500 regions (lattice_map.h), the vehicle at its
// centre, a view of 15 m; the filter holds the lattice's 324 landmarks, 8 landmarks on an
// object's face 3 m ahead and, to make up `landmarks`, landmarks far outside the view.
// With `marked` the object leaves between the detector's first two calls (untimed), so
// the fast layer marks its face and the 8 landmarks are flagged; without it nothing is
// marked. The timed calls come before the next fast differencing is due: they time the
// view bookkeeping of the step and the search for landmarks to flag, nothing else.
#include "lattice_map.h"

#include <benchmark/benchmark.h>
#include <hymm/dynamic/SlamMotionHook.h>

namespace
{
using namespace hymm::dynamic::bench;

void BM_HookAfterFrame(benchmark::State& state)
{
    LatticeMap m(500);
    const size_t total = static_cast<size_t>(state.range(0));
    const bool marked = state.range(1) != 0;
    // Filter: vehicle at the centre, lattice landmarks, the object's, far ones.
    std::vector<std::pair<long, int>> blocks;
    std::vector<V2> means;
    for (const auto& [id, p] : m.lattice.landmarks())
    {
        blocks.push_back({id, 2});
        means.push_back(p);
    }
    for (int k = 0; k < 8; ++k)
    {
        const double a = -0.28 + 0.08 * k;
        blocks.push_back({10000 + k, 2});
        means.push_back(m.centre + 3.0 * V2(std::cos(a), std::sin(a)));
    }
    for (long k = 0; blocks.size() < total; ++k)
    {
        blocks.push_back({20000 + k, 2});
        means.push_back(V2(300.0 + 5.0 * static_cast<double>(k % 100), 5.0 * static_cast<double>(k / 100)));
    }
    Eigen::VectorXd x(3 + 2 * static_cast<Eigen::Index>(means.size()));
    x.head<3>() << m.centre.x(), m.centre.y(), 0.0;
    for (size_t i = 0; i < means.size(); ++i) x.segment<2>(3 + 2 * static_cast<Eigen::Index>(i)) = means[i];
    hymm::ekf::EkfSlam ekf{hymm::ekf::EkfSlam::Options{}};
    ekf.setActiveState(x, 1e-4 * Eigen::MatrixXd::Identity(x.size(), x.size()), blocks);

    hymm::dynamic::SlamMotionHook::Options o;
    o.enabled = true;
    o.view_range_m = 15.0;
    o.prune_flagged = false;  // the filter stays as built
    o.detector.enable_slow = false;
    hymm::dynamic::SlamMotionHook hook(o);
    const hymm::dense::ScanPoints with_object = ringScan(6.0, -0.4, 0.4, 3.0), without = ringScan();
    const mrpt::math::TPose2D pose(m.centre.x(), m.centre.y(), 0.0);
    for (int k = 0; k < 10; ++k) m.map.insertScan(marked ? with_object : without, pose, m.partition);
    hook.afterFrame(m.map, m.partition, ekf, 0.0);
    for (int k = 0; k < 10; ++k) m.map.insertScan(without, pose, m.partition);
    hook.afterFrame(m.map, m.partition, ekf, 1.0);
    if (marked && hook.flagged().empty())
    {
        state.SkipWithError("the object's landmarks were not flagged");
        return;
    }
    double t = 1.0;
    for (auto _ : state)
    {
        t += 1e-4;  // the next fast differencing is due at t = 2
        benchmark::DoNotOptimize(hook.afterFrame(m.map, m.partition, ekf, t));
    }
    state.counters["landmarks"] = static_cast<double>(ekf.numLandmarks());
    state.counters["flagged"] = static_cast<double>(hook.flagged().size());
    state.counters["marked_cells"] =
        static_cast<double>(hook.detector().markedCells(hymm::dynamic::MotionKind::Fast));
}

BENCHMARK(BM_HookAfterFrame)
    ->ArgsProduct({{500, 1000, 2000, 4000}, {0, 1}})
    ->ArgNames({"landmarks", "marked"})
    ->Iterations(3000)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
