/**
 * @file PointsLayer_test.cpp
 * @brief Raw points stored in reference coordinates, thinned, rendered, serialised.
 */
#include "hymm/dense/PointsLayer.h"

#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <random>
#include <sstream>

namespace
{
using namespace hymm::dense;
using V2 = Eigen::Vector2d;

TEST(PointsLayerTest, StoresHitsAndRendersThroughAffineMap)
{
    PointsLayer layer{PointsLayer::Options()};
    RegionScan s;
    s.hits = {V2(1, 0.5), V2(0.25, 2)};
    s.rays.push_back({V2(0, 0), V2(1, 0.5), true});  // rays are not points
    layer.insert(s);
    ASSERT_EQ(layer.size(), 2u);
    const hymm::ltr::TriangleFrame ref(V2(0, 0), V2(4, 0), V2(0, 4));
    const hymm::ltr::TriangleFrame cur(V2(1, 1), V2(1, 5), V2(-3, 1));  // rotated 90 deg, shifted
    mrpt::maps::CSimplePointsMap out;
    layer.renderInto(hymm::ltr::AffineRegionMap(ref, cur), out);
    ASSERT_EQ(out.size(), 2u);
    float x, y;
    out.getPoint(0, x, y);
    EXPECT_NEAR(x, 0.5, 1e-6);  // (1, 0.5) rotated by 90 deg = (-0.5, 1), + (1, 1)
    EXPECT_NEAR(y, 2.0, 1e-6);
    mrpt::maps::COccupancyGridMap2D wrong;
    EXPECT_THROW(layer.renderInto(hymm::ltr::AffineRegionMap(), wrong), std::invalid_argument);
}

TEST(PointsLayerTest, VoxelThinningKeepsOnePointPerVoxel)
{
    PointsLayer::Options o;
    o.voxel_size_m = 0.5;
    PointsLayer layer(o);
    layer.insertPoints({V2(0.1, 0.1), V2(0.4, 0.2), V2(0.6, 0.1), V2(-0.1, 0.1)});
    EXPECT_EQ(layer.size(), 3u);
}

TEST(PointsLayerTest, RevisitCapKeepsAUniformSampleOfEveryReturn)
{
    // A wall y = 0 seen on 20 laps, 1000 noisy returns a lap (sigma 0.15 m across it).
    const double sigma = 0.15;
    const hymm::ltr::TriangleFrame::Vertices ref{{V2(0, -5), V2(10, -5), V2(5, 5)}};
    PointsLayer::Options o;
    o.max_points = 500;
    PointsLayer capped(o, ref), capped_again(o, ref);
    o.max_points = 0;
    PointsLayer all(o, ref);
    o.voxel_size_m = 0.05;
    PointsLayer voxels(o, ref);
    std::mt19937_64 rng(7);
    std::normal_distribution<double> n01(0, 1);
    std::vector<std::vector<V2>> laps(20);
    for (auto& lap : laps)
        for (int k = 0; k < 1000; ++k) lap.emplace_back(0.01 * k, sigma * n01(rng));
    for (const auto& lap : laps)
    {
        capped.insertPoints(lap);
        capped_again.insertPoints(lap);
        all.insertPoints(lap);
        voxels.insertPoints(lap);
        EXPECT_LE(capped.size(), 500u);
    }
    EXPECT_EQ(capped.size(), 500u);
    EXPECT_EQ(capped.offered(), 20000u);
    EXPECT_EQ(all.size(), 20000u);
    // Same region, same data: the same map.
    for (size_t i = 0; i < capped.size(); ++i)
        EXPECT_EQ(capped.points().getPointsBufferRef_y()[i], capped_again.points().getPointsBufferRef_y()[i]);
    const auto spread = [](const PointsLayer& l) {
        double s2 = 0;
        for (const float y : l.points().getPointsBufferRef_y()) s2 += static_cast<double>(y) * y;
        return std::sqrt(s2 / static_cast<double>(l.size()));
    };
    // The sample keeps the returns' spread about the wall (500 samples: +-3.2 % 1-sigma);
    // one point per voxel does not: over the laps the tails fill every voxel.
    EXPECT_NEAR(spread(capped), sigma, 0.12 * sigma);
    EXPECT_NEAR(spread(all), sigma, 0.03 * sigma);
    EXPECT_GT(spread(voxels), 1.3 * sigma);  // 1.49 sigma measured
    // Later laps replace earlier ones: every lap is in the sample about equally (the
    // x position tells the order within a lap only, so count by lap through y values).
    size_t from_last_lap = 0;
    for (const float y : capped.points().getPointsBufferRef_y())
        for (const V2& p : laps.back()) from_last_lap += static_cast<float>(p.y()) == y;
    EXPECT_GT(from_last_lap, 5u);   // expected 25
    EXPECT_LT(from_last_lap, 60u);
}

TEST(PointsLayerTest, SaveLoadRoundTripIsExact)
{
    PointsLayer a{PointsLayer::Options()};
    a.insertPoints({V2(0.123456789, -7.25), V2(1e-3, 123.456)});
    std::stringstream ss;
    a.save(ss);
    PointsLayer b{PointsLayer::Options()};
    b.load(ss);
    ASSERT_EQ(b.size(), 2u);
    for (size_t i = 0; i < 2; ++i)
    {
        EXPECT_EQ(a.points().getPointsBufferRef_x()[i], b.points().getPointsBufferRef_x()[i]);
        EXPECT_EQ(a.points().getPointsBufferRef_y()[i], b.points().getPointsBufferRef_y()[i]);
    }
    std::stringstream bad("points 3\n1 2\n");
    EXPECT_THROW(b.load(bad), std::runtime_error);
}

}  // namespace
