/**
 * @file HybridMetricMap_test.cpp
 * @brief Multi-region fusion of a synthetic wall scan, locality of the per-scan work,
 *        persistence and layer selection.
 */
#include "hymm/dense/HybridMetricMap.h"

#include "hymm/dense/map_images.h"
#include "hymm/dense/outline_metrics.h"
#include "synthetic_partition.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace
{
using namespace hymm::dense;
using namespace hymm::dense::synthetic;
using V2 = Eigen::Vector2d;

HybridMetricMap::Options mapOptions()
{
    HybridMetricMap::Options o;
    o.occupancy.cell_size_m = 0.1;
    return o;
}

// A region refused by insertScan's filter (its local frame not known well enough relative
// to the vehicle, Sec. 3.6) gets neither returns nor free space; its returns come back.
TEST(HybridMetricMapTest, RefusedRegionsGetNothingAndTheirReturnsComeBack)
{
    WallWorld w;
    const ScanPoints scan = wallScan(kVehicle, kMount, kWallX, kBeams, kHalfFov);
    HybridMetricMap all(mapOptions()), some(mapOptions());
    const auto st_all = all.insertScan(scan, kVehicle, w.partition);
    long refused = -1;  // a region that holds returns
    for (long id : all.regionIds())
        if (refused < 0 && all.localMap(id)->layerAs<PointsLayer>(PointsLayer::kKind)->points().size() > 0)
            refused = id;
    ASSERT_GE(refused, 0);
    const auto st = some.insertScan(scan, kVehicle, w.partition, [&](long id) { return id != refused; });
    EXPECT_EQ(st.regions_withheld, 1u);
    EXPECT_GT(st.returns_withheld, 0u);
    EXPECT_EQ(some.localMap(refused), nullptr);
    EXPECT_EQ(st.regions_updated + 1, st_all.regions_updated);
    EXPECT_EQ(st.returns_outside, st_all.returns_outside);
    EXPECT_EQ(st.returns_stored + st.returns_withheld, st_all.returns_stored);
    ASSERT_EQ(st.withheld.size(), st.returns_withheld);
    for (const V2& p : st.withheld) EXPECT_EQ(w.partition.findRegion(p), std::optional<long>(refused));
    // Every other region holds exactly what it holds without the filter.
    for (long id : some.regionIds())
    {
        const auto* a = all.localMap(id)->layerAs<PointsLayer>(PointsLayer::kKind);
        const auto* b = some.localMap(id)->layerAs<PointsLayer>(PointsLayer::kKind);
        ASSERT_TRUE(a && b);
        EXPECT_EQ(a->points().size(), b->points().size());
    }
}

TEST(HybridMetricMapTest, WallScanIsStoredOnTheWallAcrossRegions)
{
    WallWorld w;
    HybridMetricMap map(mapOptions());
    const ScanPoints scan = wallScan(kVehicle, kMount, kWallX, kBeams, kHalfFov);
    // Analytic returns: y = 7.5 + 13.7 tan(phi); those with y outside [0, 15] are in no region.
    size_t expected_outside = 0;
    for (int k = 0; k < kBeams; ++k)
    {
        const double phi = -kHalfFov + 2 * kHalfFov * k / (kBeams - 1);
        const double y = 7.5 + (kWallX - 3.3) * std::tan(phi);
        if (y < 0 || y > 15) ++expected_outside;
    }
    ASSERT_GT(expected_outside, 0u);
    HybridMetricMap::InsertStats st;
    for (int rep = 0; rep < 3; ++rep) st = map.insertScan(scan, kVehicle, w.partition);
    EXPECT_EQ(st.beams, static_cast<size_t>(kBeams));
    EXPECT_EQ(st.returns_outside, expected_outside);
    EXPECT_EQ(st.returns_stored, kBeams - expected_outside);
    ASSERT_EQ(st.unassigned.size(), expected_outside);
    ASSERT_EQ(st.unassigned_source.size(), expected_outside);
    const mrpt::math::TPose2D sensor = kVehicle + scan.sensor_on_vehicle;
    for (size_t i = 0; i < st.unassigned.size(); ++i)
    {
        const V2& p = st.unassigned[i];
        EXPECT_NEAR(p.x(), kWallX, 1e-9);
        EXPECT_TRUE(p.y() < 0 || p.y() > 15);
        // The source names the return whose measurement lands there.
        const V2 z = scan.rangeBearing(st.unassigned_source[i]);
        const V2 g(sensor.x + z[0] * std::cos(sensor.phi + z[1]), sensor.y + z[0] * std::sin(sensor.phi + z[1]));
        EXPECT_NEAR((g - p).norm(), 0.0, 1e-9);
    }
    EXPECT_GE(st.regions_updated, 8u);  // the beams cross many triangles
    EXPECT_LE(st.regions_visited, 24u);

    // Stored points lie on the wall, in reference (= current, nothing moved) coordinates.
    mrpt::maps::CSimplePointsMap pts;
    map.renderPoints(w.partition, pts);
    EXPECT_EQ(pts.size(), 3 * st.returns_stored);
    for (const V2& p : pointsOf(pts)) EXPECT_NEAR(p.x(), kWallX, 1e-4);
    for (const long id : map.regionIds())
    {
        const auto* layer = map.localMap(id)->layerAs<PointsLayer>(PointsLayer::kKind);
        ASSERT_NE(layer, nullptr);
        for (const V2& p : pointsOf(layer->points())) EXPECT_NEAR(p.x(), kWallX, 1e-4);
    }

    // Occupied cells (P > 0.8) within one cell of the wall, and they cover it.
    mrpt::maps::COccupancyGridMap2D og;
    map.renderOccupancy(w.partition, 0.1, og);
    const auto occ = occupiedCellCentres(og, 0.8);
    ASSERT_FALSE(occ.empty());
    for (const V2& c : occ) EXPECT_LE(std::abs(c.x() - kWallX), 0.1 + 1e-6) << c.transpose();
    OutlineMetricsOptions mo;
    mo.closed = false;
    const auto m = evaluateOutlines(occ, {{V2(kWallX, 0.3), V2(kWallX, 14.7)}}, mo);
    EXPECT_GT(m.coverage, 0.99);
    EXPECT_LT(m.mean_distance_m, 0.06);

    // Free cells along the beams (away from the return and from the lattice border).
    const auto world = scan.toWorld(kVehicle, 25.0);
    size_t samples = 0, free = 0, occupied = 0;
    for (const auto& b : world.beams)
        for (double f = 0.05; f < 1.0; f += 0.05)
        {
            const V2 p = world.sensor + f * (b.end - world.sensor);
            if ((b.end - p).norm() < 0.3 || p.y() < 0.1 || p.y() > 14.9) continue;
            const float prob = og.getPos(static_cast<float>(p.x()), static_cast<float>(p.y()));
            ++samples;
            if (prob < 0.3f) ++free;
            if (prob > 0.5f) ++occupied;
        }
    ASSERT_GT(samples, 1000u);
    EXPECT_EQ(occupied, 0u);
    EXPECT_GT(static_cast<double>(free) / static_cast<double>(samples), 0.97);
}

/** Ring of returns 8 m around the sensor, 361 beams. */
ScanPoints ringScan()
{
    ScanPoints s;
    for (int k = 0; k < 361; ++k)
    {
        const double a = 2 * M_PI * k / 361.0;
        s.points.emplace_back(8.0 * std::cos(a), 8.0 * std::sin(a));
    }
    return s;
}

HybridMetricMap::InsertStats insertIntoLattice(const Lattice& lat, size_t regions, const V2& at)
{
    IndependentLandmarksView view(lat.landmarks());
    hymm::ltr::RegionPartition partition(permissivePartitionOptions());
    addRegions(partition, view, lat.triangles(at), regions);
    HybridMetricMap map(mapOptions());
    return map.insertScan(ringScan(), {at.x(), at.y(), 0.3}, partition);
}

TEST(HybridMetricMapTest, ScanTouchesOnlyNearbyRegions)
{
    const V2 at(27.4, 27.1);
    // Same 5 m lattice around the scan; the large one extends far beyond it.
    const auto small = insertIntoLattice({16, 16, 5.0, V2(0, 0)}, 400, at);
    const auto large = insertIntoLattice({33, 33, 5.0, V2(-50, -50)}, 2000, at);
    const auto tiny = insertIntoLattice({12, 12, 5.0, V2(0, 0)}, 10, at);
    EXPECT_EQ(small.regions_visited, large.regions_visited);
    EXPECT_EQ(small.regions_updated, large.regions_updated);
    EXPECT_EQ(small.returns_stored, large.returns_stored);
    EXPECT_EQ(large.returns_stored, 361u);
    EXPECT_LT(large.regions_visited, 100u);  // of 2000
    EXPECT_LE(tiny.regions_visited, 10u);
    EXPECT_GT(tiny.returns_outside, 0u);
}

TEST(HybridMetricMapTest, SaveLoadRoundTripAndStaleRegions)
{
    WallWorld w;
    HybridMetricMap map(mapOptions());
    map.insertScan(wallScan(kVehicle, kMount, kWallX, kBeams, kHalfFov), kVehicle, w.partition);
    std::stringstream ss;
    map.save(ss);
    HybridMetricMap copy(mapOptions());
    copy.load(ss);
    std::stringstream s1, s2;
    map.save(s1);
    copy.save(s2);
    EXPECT_EQ(s1.str(), s2.str());
    EXPECT_EQ(copy.size(), map.size());
    EXPECT_GT(copy.memoryBytes(), 1000u);

    const long gone = map.regionIds().front();
    ASSERT_TRUE(w.partition.removeRegion(gone));
    EXPECT_EQ(map.removeStaleRegions(w.partition), std::vector<long>{gone});
    EXPECT_EQ(map.localMap(gone), nullptr);

    std::stringstream bad("hybrid_metric_map 1\nregion 3 0x0p+0");
    EXPECT_THROW(copy.load(bad), std::runtime_error);
}

TEST(HybridMetricMapTest, OnlyEnabledLayersAreBuilt)
{
    WallWorld w;
    auto o = mapOptions();
    o.enable_points = false;
    HybridMetricMap map(o);
    const auto st = map.insertScan(wallScan(kVehicle, kMount, kWallX, kBeams, kHalfFov), kVehicle, w.partition);
    ASSERT_GT(st.regions_updated, 0u);
    for (const long id : map.regionIds())
        EXPECT_EQ(map.localMap(id)->layerKinds(), std::vector<std::string>{OccupancyLayer::kKind});
    mrpt::maps::CSimplePointsMap pts;
    map.renderPoints(w.partition, pts);
    EXPECT_EQ(pts.size(), 0u);
}

TEST(HybridMetricMapTest, WritesPngPictures)
{
    WallWorld w;
    HybridMetricMap map(mapOptions());
    map.insertScan(wallScan(kVehicle, kMount, kWallX, kBeams, kHalfFov), kVehicle, w.partition);
    mrpt::maps::COccupancyGridMap2D og;
    map.renderOccupancy(w.partition, 0.1, og);
    mrpt::maps::CSimplePointsMap pts;
    map.renderPoints(w.partition, pts);
    const std::string dir = ::testing::TempDir();
    saveOccupancyPng(og, dir + "dense_occ.png", &w.partition);
    savePointsPng(pts, dir + "dense_pts.png", 0.05, &w.partition);
    for (const char* f : {"dense_occ.png", "dense_pts.png"})
    {
        std::ifstream in(dir + f, std::ios::binary);
        char sig[4] = {};
        in.read(sig, 4);
        EXPECT_EQ(std::string(sig + 1, 3), "PNG") << f;
    }
    EXPECT_THROW(saveOccupancyPng(og, "/nonexistent-dir/x.png"), std::runtime_error);
}

}  // namespace
