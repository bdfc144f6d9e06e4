/**
 * @file DenseInsert_bench.cpp
 * @brief Cost of the dense layers: one 361-beam scan into points + occupancy against
 *        the number of regions and landmarks (must stay flat), and global rendering
 *        against map area.
 *
 * Landmarks sit on an 8 m lattice; the regions are the lattice triangles nearest the
 * scan, so every configuration covers the scanned area the same way and only the size
 * of the rest of the map changes. The scan: 361 beams over 180 deg inside a square
 * room of half-size 7 m (max range 25 m, 0.1 m cells).
 */
#include "hymm/dense/HybridMetricMap.h"
#include "synthetic_partition.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

namespace
{
using namespace hymm::dense;
using namespace hymm::dense::synthetic;
using V2 = Eigen::Vector2d;

constexpr double kSpacing = 8.0;

ScanPoints roomScan()
{
    ScanPoints s;
    for (int k = 0; k < 361; ++k)
    {
        const double a = -M_PI / 2 + M_PI * k / 360.0;
        const double r = 7.0 / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)));
        s.points.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    return s;
}

struct World
{
    Lattice lattice;
    std::unique_ptr<IndependentLandmarksView> view;
    std::unique_ptr<hymm::ltr::RegionPartition> partition;

    World(int side, size_t regions, const V2& centre)
        : lattice{side, side, kSpacing, V2(0, 0)},
          view(std::make_unique<IndependentLandmarksView>(lattice.landmarks())),
          partition(std::make_unique<hymm::ltr::RegionPartition>(permissivePartitionOptions()))
    {
        addRegions(*partition, *view, lattice.triangles(centre), regions);
    }
};

HybridMetricMap::Options mapOptions()
{
    HybridMetricMap::Options o;
    o.occupancy.cell_size_m = 0.1;
    o.points.voxel_size_m = 0.02;  // bounds memory over many identical iterations
    return o;
}

/** Args: number of regions, number of landmarks. */
void BM_InsertScan(benchmark::State& state)
{
    const auto regions = static_cast<size_t>(state.range(0));
    const int side = static_cast<int>(std::lround(std::sqrt(static_cast<double>(state.range(1)))));
    const int mid = side / 2;
    const V2 vehicle = kSpacing * V2(mid + 0.3, mid + 0.4);
    World w(side, regions, vehicle + V2(3.5, 0));
    HybridMetricMap map(mapOptions());
    const ScanPoints scan = roomScan();
    const mrpt::math::TPose2D pose{vehicle.x(), vehicle.y(), 0.0};
    HybridMetricMap::InsertStats st;
    for (auto _ : state)
    {
        st = map.insertScan(scan, pose, *w.partition);
        benchmark::DoNotOptimize(st.returns_stored);
    }
    state.counters["regions_total"] = static_cast<double>(w.partition->size());
    state.counters["landmarks"] = static_cast<double>(side * side);
    state.counters["regions_visited"] = static_cast<double>(st.regions_visited);
    state.counters["returns_stored"] = static_cast<double>(st.returns_stored);
}
BENCHMARK(BM_InsertScan)
    ->Args({10, 100})
    ->Args({100, 100})
    ->Args({100, 2000})
    ->Args({1000, 1000})
    ->Args({2000, 2000})
    ->Repetitions(5)
    ->ReportAggregatesOnly(true)
    ->Unit(benchmark::kMicrosecond);

/** Arg: lattice side (landmarks per row); every triangle is a region and holds data. */
struct RenderWorld
{
    World world;
    HybridMetricMap map{mapOptions()};
    explicit RenderWorld(int side)
        : world(side, static_cast<size_t>(2 * (side - 1) * (side - 1)), V2::Zero())
    {
        const ScanPoints scan = roomScan();
        for (int i = 0; i + 1 < side; i += 2)
            for (int j = 0; j + 1 < side; j += 2)
                map.insertScan(scan, {kSpacing * (i + 0.5), kSpacing * (j + 0.5), 0.0}, *world.partition);
    }
};

void BM_RenderOccupancy(benchmark::State& state)
{
    RenderWorld rw(static_cast<int>(state.range(0)));
    mrpt::maps::COccupancyGridMap2D og;
    for (auto _ : state)
    {
        rw.map.renderOccupancy(*rw.world.partition, 0.1, og);
        benchmark::DoNotOptimize(og.getSizeX());
    }
    state.counters["area_m2"] = std::pow(kSpacing * (state.range(0) - 1), 2);
    state.counters["regions"] = static_cast<double>(rw.map.size());
}
BENCHMARK(BM_RenderOccupancy)->Arg(6)->Arg(11)->Arg(21)->Unit(benchmark::kMillisecond);

void BM_RenderPoints(benchmark::State& state)
{
    RenderWorld rw(static_cast<int>(state.range(0)));
    mrpt::maps::CSimplePointsMap pts;
    for (auto _ : state)
    {
        rw.map.renderPoints(*rw.world.partition, pts);
        benchmark::DoNotOptimize(pts.size());
    }
    state.counters["area_m2"] = std::pow(kSpacing * (state.range(0) - 1), 2);
    state.counters["points"] = static_cast<double>(pts.size());
}
BENCHMARK(BM_RenderPoints)->Arg(6)->Arg(11)->Arg(21)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
