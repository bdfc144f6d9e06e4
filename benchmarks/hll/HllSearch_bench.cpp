/**
 * @file HllSearch_bench.cpp
 * @brief Cost of one high-level landmark search (thesis 6.1.3: "the algorithm only
 *        searches for HLL in the local areas around the vehicle ... This will make the
 *        computational cost of the HLLs search independent of the global map size")
 *        against the number of regions of the map: 10 to 2000.
 *
 * Landmarks on an 8 m lattice; the 10 triangles nearest the vehicle are always the
 * same, the others are added farthest first (the map grows away from the vehicle), and
 * every region holds occupancy and SOG content: a 10 m square room scanned from inside
 * its centroid's neighbourhood. One iteration = HllDetector::search() around the vehicle
 * (box lookup, local occupancy render, Harris corners, pairs, rectangles, SOG counts).
 *
 * BM_TemplateAugmentation: the other read of the dense map around a place (thesis 6.2),
 * the augmentation of a scan landmark's template before an alignment: a 6 m template
 * (one corner of the room around the vehicle) whose pose landmark is in an EKF,
 * ScanLandmarkMap::augmentedTemplate with DenseSlam's augmenter (denseGaussiansInBox:
 * box lookup, SOG means at the current affine maps, into the landmark frame, thinned).
 */
#include <hymm/dense/HybridMetricMap.h>
#include <hymm/denseslam/dense_gaussians.h>
#include <hymm/ekf/EkfSlam.h>
#include <hymm/hll/HllDetector.h>
#include <hymm/scanslam/ScanLandmarkMap.h>

#include "synthetic_partition.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace
{
using namespace hymm::dense;
using namespace hymm::dense::synthetic;
using V2 = Eigen::Vector2d;

constexpr double kSpacing = 8.0;
constexpr int kSide = 46;  // 2 x 45 x 45 = 4050 triangles: enough for 2000 regions
constexpr size_t kLocal = 10;

/** A square room of half-size 5 m seen from its centre: four walls, four corners. */
ScanPoints roomScan()
{
    ScanPoints s;
    for (int k = 0; k < 720; ++k)
    {
        const double a = -M_PI + 2 * M_PI * k / 720.0;
        const double r = 5.0 / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)));
        s.points.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    s.range_std_m = 0.05;
    s.bearing_std_rad = 0.5 * M_PI / 180;
    return s;
}

struct Map
{
    Lattice lattice{kSide, kSide, kSpacing, V2(0, 0)};
    std::unique_ptr<IndependentLandmarksView> view;
    std::unique_ptr<hymm::ltr::RegionPartition> partition;
    std::unique_ptr<HybridMetricMap> hybrid;
    V2 vehicle;

    explicit Map(size_t regions)
        : view(std::make_unique<IndependentLandmarksView>(lattice.landmarks())),
          partition(std::make_unique<hymm::ltr::RegionPartition>(permissivePartitionOptions()))
    {
        const int mid = kSide / 2;
        vehicle = kSpacing * V2(mid + 0.3, mid + 0.4);
        auto tris = lattice.triangles(vehicle);
        if (regions > kLocal) std::reverse(tris.begin() + kLocal, tris.end());
        addRegions(*partition, *view, tris, regions);
        HybridMetricMap::Options o;
        o.enable_points = false;
        o.enable_occupancy = true;
        o.enable_sog = true;
        o.occupancy.cell_size_m = 0.2;
        hybrid = std::make_unique<HybridMetricMap>(o);
        // Content in every region: the room around each region's centroid (near the
        // vehicle: around the vehicle itself, twice, so the local layers are the same
        // in every configuration).
        const ScanPoints room = roomScan();
        for (int k = 0; k < 2; ++k) hybrid->insertScan(room, {vehicle.x(), vehicle.y(), 0.0}, *partition);
        for (long id : partition->regionIds())
        {
            const auto& v = partition->region(id).current;
            const V2 c = (v[0] + v[1] + v[2]) / 3.0;
            if ((c - vehicle).norm() < 40) continue;
            hybrid->insertScan(room, {c.x(), c.y(), 0.0}, *partition);
        }
    }
};

/** The map sizes of both benchmarks: 10 to 2000 regions, medians of 5 repetitions. */
void mapSizes(benchmark::internal::Benchmark* b)
{
    for (const int n : {10, 100, 500, 1000, 2000}) b->Arg(n);
    b->Repetitions(5)->ReportAggregatesOnly(true)->Unit(benchmark::kMicrosecond);
}

void BM_HllSearch(benchmark::State& state)
{
    const auto regions = static_cast<size_t>(state.range(0));
    Map m(regions);
    hymm::hll::HllDetector::Options o;
    o.search_half_size_m = 12;  // the box meets the same local regions in every case
    o.min_gaussians = 50;
    const hymm::hll::HllDetector det(o);
    hymm::hll::HllDetector::Search s;
    for (auto _ : state)
    {
        s = det.search(m.vehicle, *m.partition, *m.hybrid, {}, 0.0);
        benchmark::DoNotOptimize(s.candidates.data());
    }
    state.counters["regions_total"] = static_cast<double>(m.partition->size());
    state.counters["regions_searched"] = static_cast<double>(s.regions);
    state.counters["corners"] = static_cast<double>(s.corners.size());
    state.counters["candidates"] = static_cast<double>(s.candidates.size());
    state.counters["gaussians"] = static_cast<double>(s.gaussians.size());
}
BENCHMARK(BM_HllSearch)->Apply(mapSizes);

void BM_TemplateAugmentation(benchmark::State& state)
{
    const auto regions = static_cast<size_t>(state.range(0));
    Map m(regions);
    using namespace hymm::scanslam;
    // The room's south-west corner as the template: 3 m of each wall, in a frame at the
    // corner's centroid (global orientation 0), as a pose landmark seen from the vehicle.
    ScanTemplate tpl;
    const V2 corner = m.vehicle + V2(-5, -5);
    std::vector<V2> pts;
    for (int k = 0; k <= 30; ++k) pts.push_back(corner + V2(0.1 * k, 0));
    for (int k = 1; k <= 30; ++k) pts.push_back(corner + V2(0, 0.1 * k));
    V2 c = V2::Zero();
    for (const V2& p : pts) c += p;
    c /= static_cast<double>(pts.size());
    for (const V2& p : pts) tpl.sog.add(p - c, 0.0025 * Mat2::Identity());
    hymm::ekf::EkfSlam ekf{hymm::ekf::EkfSlam::Options{}};
    ekf.reset(Eigen::Vector3d(m.vehicle.x(), m.vehicle.y(), 0.0), 1e-4 * Eigen::Matrix3d::Identity());
    const Vec3 z(c.x() - m.vehicle.x(), c.y() - m.vehicle.y(), 0.0);
    const long id = ekf.addPoseLandmark(z, 1e-3 * Mat3::Identity(), Vec3::Zero());
    ScanLandmarkMap::Options o;
    o.augment_above_std_m = 0.5;
    ScanLandmarkMap map(o, Segmenter::Options{}, SegmentAcceptance::Options{}, makeMatcher("sog"));
    hymm::denseslam::DenseGaussiansStats st;
    map.setAugmenter([&](const V2& lo, const V2& hi) {
        return hymm::denseslam::denseGaussiansInBox(*m.partition, *m.hybrid, lo, hi, 0.05, &st);
    });
    ScanTemplate aug;
    for (auto _ : state)
    {
        aug = map.augmentedTemplate(ekf, id, tpl);
        benchmark::DoNotOptimize(aug.sog.points.data());
    }
    state.counters["regions_total"] = static_cast<double>(m.partition->size());
    state.counters["regions_read"] = static_cast<double>(st.regions);
    state.counters["gaussians_read"] = static_cast<double>(st.read);
    state.counters["gaussians_added"] = static_cast<double>(aug.sog.size() - tpl.sog.size());
}
BENCHMARK(BM_TemplateAugmentation)->Apply(mapSizes);

}  // namespace

BENCHMARK_MAIN();
