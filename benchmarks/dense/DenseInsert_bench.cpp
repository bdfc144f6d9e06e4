/**
 * @file DenseInsert_bench.cpp
 * @brief Cost of the dense layers: one 361-beam scan into points + occupancy against
 *        the number of regions and landmarks (must stay flat), the same per layer
 *        (points, occupancy, particles, SOG, property, all five) against the number of
 *        regions (thesis Sec. 4.5 multi-layer maps), the same with a share of beams
 *        that return nothing (HybridMetricMap no_return_free_range_m off / on), and
 *        global rendering against map area.
 *
 * Landmarks sit on an 8 m lattice; the regions are the lattice triangles nearest the
 * scan, so every configuration covers the scanned area the same way and only the size
 * of the rest of the map changes. The scan: 361 beams over 180 deg inside a square
 * room of half-size 7 m (max range 25 m, 0.1 m cells).
 */
#include "hymm/dense/HybridMetricMap.h"
#include "synthetic_partition.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace
{
using namespace hymm::dense;
using namespace hymm::dense::synthetic;
using V2 = Eigen::Vector2d;

constexpr double kSpacing = 8.0;

constexpr int kBeams = 361;

/** The room seen from its centre; with `noise` > 0 the ranges carry Gaussian noise of
 *  that sigma [m] drawn from `rng`. */
ScanPoints roomScan(double noise = 0.0, std::mt19937* rng = nullptr)
{
    ScanPoints s;
    std::normal_distribution<double> n01(0.0, 1.0);
    for (int k = 0; k < kBeams; ++k)
    {
        const double a = -M_PI / 2 + M_PI * k / (kBeams - 1.0);
        double r = 7.0 / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)));
        if (noise > 0 && rng) r += noise * n01(*rng);
        s.points.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    return s;
}

struct World
{
    Lattice lattice;
    std::unique_ptr<IndependentLandmarksView> view;
    std::unique_ptr<hymm::ltr::RegionPartition> partition;

    /** The `regions` triangles nearest `centre`; with `local` > 0, only the `local`
     *  nearest and then the farthest ones (the map grows away from the scan). */
    World(int side, size_t regions, const V2& centre, size_t local = 0)
        : lattice{side, side, kSpacing, V2(0, 0)},
          view(std::make_unique<IndependentLandmarksView>(lattice.landmarks())),
          partition(std::make_unique<hymm::ltr::RegionPartition>(permissivePartitionOptions()))
    {
        auto tris = lattice.triangles(centre);
        if (local > 0 && regions > local)
            std::reverse(tris.begin() + static_cast<std::ptrdiff_t>(local), tris.end());
        addRegions(*partition, *view, tris, regions);
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

// --- one layer at a time ------------------------------------------------------------

/** The layers of BM_InsertScanLayer, by its first argument; the last is all five. */
const std::array<const char*, 6> kLayerNames = {"points", "occupancy", "particles",
                                                "sog",    "property",  "all"};

HybridMetricMap::Options layerOptions(size_t layer)
{
    HybridMetricMap::Options o = mapOptions();
    const bool all = layer == kLayerNames.size() - 1;
    o.enable_points = all || layer == 0;
    o.enable_occupancy = all || layer == 1;
    o.enable_particles = all || layer == 2;
    o.enable_sog = all || layer == 3;
    o.enable_property = all || layer == 4;
    // Bounded per region, so that thousands of inserts of the same room reach a steady
    // state (unbounded, as in the thesis, the set grows with every scan and the time
    // per scan with it, whatever the size of the map).
    o.particles.max_particles = 4000;
    return o;
}

// Noisy copies of the room scan cycled through, each with intensities as values (the
// property layer needs them); the map is filled with them before timing.
constexpr int kScanVariants = 16;
constexpr int kWarmUpScans = 3 * kScanVariants;
constexpr int kLatticeSide = 45;  // 2025 landmarks, 3872 triangles: room for 2000 regions
// The scan always meets the same kLocalRegions regions, the triangles nearest the
// room; the others are the farthest of the lattice (over 100 m away), so only the size
// of the map changes. With the vehicle (0.1, 0.5) spacings into its lattice square the
// 10 nearest triangles hold every return of the scan (at BM_InsertScan's (0.3, 0.4)
// they miss a sixth of it).
constexpr size_t kLocalRegions = 10;
const V2 kLayerVehicleOffset(0.1, 0.5);

std::vector<ScanPoints> noisyRoomScans()
{
    std::mt19937 rng(7);
    std::normal_distribution<double> n01(0.0, 1.0);
    std::vector<ScanPoints> scans;
    for (int v = 0; v < kScanVariants; ++v)
    {
        ScanPoints s = roomScan(0.02, &rng);
        for (int k = 0; k < kBeams; ++k) s.values.push_back(100.0 + 4.0 * n01(rng));
        scans.push_back(std::move(s));
    }
    return scans;
}

/** Warms `map` up, then times one insertScan per iteration, cycling through `scans`;
 *  returns the statistics of the last timed scan. */
HybridMetricMap::InsertStats timeInserts(benchmark::State& state, HybridMetricMap& map,
                                         const std::vector<ScanPoints>& scans,
                                         const mrpt::math::TPose2D& pose, const World& w)
{
    for (int i = 0; i < kWarmUpScans; ++i)
        map.insertScan(scans[i % kScanVariants], pose, *w.partition);
    HybridMetricMap::InsertStats st;
    size_t i = 0;
    for (auto _ : state)
    {
        st = map.insertScan(scans[i++ % kScanVariants], pose, *w.partition);
        benchmark::DoNotOptimize(st.returns_stored);
    }
    return st;
}

/** Args: layer (index into kLayerNames), number of regions. */
void BM_InsertScanLayer(benchmark::State& state)
{
    const auto layer = static_cast<size_t>(state.range(0));
    const auto regions = static_cast<size_t>(state.range(1));
    const int mid = kLatticeSide / 2;
    const V2 vehicle = kSpacing * (V2(mid, mid) + kLayerVehicleOffset);
    World w(kLatticeSide, regions, vehicle + V2(3.5, 0), kLocalRegions);
    HybridMetricMap map(layerOptions(layer));
    const std::vector<ScanPoints> scans = noisyRoomScans();
    const mrpt::math::TPose2D pose{vehicle.x(), vehicle.y(), 0.0};
    const HybridMetricMap::InsertStats st = timeInserts(state, map, scans, pose, w);
    if (st.returns_stored != static_cast<size_t>(kBeams) || st.regions_visited != kLocalRegions)
        state.SkipWithError("the scan does not meet exactly the local regions, holding it all");
    state.SetLabel(kLayerNames.at(layer));
    state.counters["regions_total"] = static_cast<double>(w.partition->size());
    state.counters["regions_visited"] = static_cast<double>(st.regions_visited);
    state.counters["returns_stored"] = static_cast<double>(st.returns_stored);
    double items = 0;  // points, cells, particles, Gaussians held after the run
    for (const long id : map.regionIds())
        for (const auto& kind : map.enabledKinds())
            if (const DenseLayer* l = map.localMap(id)->layer(kind))
                items += static_cast<double>(l->size());
    state.counters["map_items"] = items;
}
BENCHMARK(BM_InsertScanLayer)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5}, {10, 100, 1000, 2000}})
    ->Unit(benchmark::kMicrosecond);

// --- beams with no return ----------------------------------------------------------

// The room with a doorway: the beams within +-kDoorwayHalfDeg of the room's axis see
// through it and return nothing (81 of the 361 beams, 22%).
constexpr double kDoorwayHalfDeg = 20.0;
constexpr double kNoReturnRange = 15.0;  // [m] no_return_free_range_m when on

std::vector<ScanPoints> doorwayScans()
{
    std::vector<ScanPoints> scans = noisyRoomScans();
    for (ScanPoints& s : scans)
    {
        ScanPoints d;
        d.sensor_on_vehicle = s.sensor_on_vehicle;
        for (size_t k = 0; k < s.points.size(); ++k)
        {
            const double a = std::atan2(s.points[k].y(), s.points[k].x());
            if (std::abs(a) <= kDoorwayHalfDeg * M_PI / 180)
                d.no_return_bearings.push_back(a);
            else
            {
                d.points.push_back(s.points[k]);
                d.values.push_back(s.values[k]);
            }
        }
        s = std::move(d);
    }
    return scans;
}

/** Args: layer (index into kLayerNames); mode: 0 = no-return beams ignored (the
 *  default, no_return_free_range_m = 0), 1 = free space up to kNoReturnRange, 2 = as
 *  1 with the particle layer's free-space protection off, 3 = as 0 with it off (the
 *  free-space step before no-return beams and protection). 100 regions, as
 *  BM_InsertScanLayer otherwise. */
void BM_InsertScanNoReturn(benchmark::State& state)
{
    const auto layer = static_cast<size_t>(state.range(0));
    const auto mode = state.range(1);
    const int mid = kLatticeSide / 2;
    const V2 vehicle = kSpacing * (V2(mid, mid) + kLayerVehicleOffset);
    World w(kLatticeSide, 100, vehicle + V2(3.5, 0), kLocalRegions);
    HybridMetricMap::Options o = layerOptions(layer);
    const bool no_return_on = mode == 1 || mode == 2;
    o.no_return_free_range_m = no_return_on ? kNoReturnRange : 0.0;
    o.particles.free_space_protection = mode < 2;
    HybridMetricMap map(o);
    const std::vector<ScanPoints> scans = doorwayScans();
    const mrpt::math::TPose2D pose{vehicle.x(), vehicle.y(), 0.0};
    const HybridMetricMap::InsertStats st = timeInserts(state, map, scans, pose, w);
    const size_t no_return = scans[0].no_return_bearings.size();
    if (st.returns_stored != kBeams - no_return || st.no_return != (no_return_on ? no_return : 0))
        state.SkipWithError("the scan does not hold the expected returns / no-return beams");
    const char* modes[] = {" off", " on", " on, unprotected", " off, unprotected"};
    state.SetLabel(std::string(kLayerNames.at(layer)) + modes[mode]);
    state.counters["no_return_beams"] = static_cast<double>(no_return);
    state.counters["regions_updated"] = static_cast<double>(st.regions_updated);
}
BENCHMARK(BM_InsertScanNoReturn)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5}, {0, 1}})
    ->ArgsProduct({{2, 5}, {2, 3}})
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
