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

/** RMS distance of the stored points from the wall y = 0. */
double spread(const PointsLayer& layer)
{
    double s2 = 0;
    for (const float y : layer.points().getPointsBufferRef_y()) s2 += static_cast<double>(y) * y;
    return std::sqrt(s2 / static_cast<double>(layer.size()));
}

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
    o.max_points_per_cell = 0;  // the cap alone
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

TEST(PointsLayerTest, AreaBoundLevelsOffWithTheSurfacesAreaNotTheLaps)
{
    // Two regions, a 2 m and a 10 m wall, each seen on 40 laps with 400 returns a lap
    // (sigma 0.15 m across it, 0.05 m cells of the bound: the walls' noise bands are
    // ~40 x 12 and ~200 x 12 cells).
    const double sigma = 0.15;
    const hymm::ltr::TriangleFrame::Vertices ref{{V2(0, -5), V2(10, -5), V2(5, 5)}};
    PointsLayer::Options o;
    o.max_points = 100000;
    o.max_points_per_cell = 2;
    o.area_cell_m = 0.05;
    PointsLayer shortw(o, ref), longw(o, ref);
    std::mt19937_64 rng(11);
    std::normal_distribution<double> n01(0, 1);
    std::uniform_real_distribution<double> u01(0, 1);
    std::vector<size_t> short_size, long_size;
    std::vector<V2> last_lap;
    for (int lap = 0; lap < 40; ++lap)
    {
        std::vector<V2> s, l;
        for (int k = 0; k < 400; ++k)
        {
            s.emplace_back(2.0 * u01(rng), sigma * n01(rng));
            l.emplace_back(10.0 * u01(rng), sigma * n01(rng));
        }
        shortw.insertPoints(s);
        longw.insertPoints(l);
        short_size.push_back(shortw.size());
        long_size.push_back(longw.size());
        EXPECT_LE(shortw.size(), shortw.limit());
        EXPECT_LE(longw.size(), longw.limit());
        last_lap = l;
    }
    // Held by the area, not by max_points: the short wall's sample stops growing early
    // (the long wall's, 5 times the area, later), and neither grows by more than a few
    // points a lap at the end.
    EXPECT_LT(short_size.back(), 2000u);
    EXPECT_GT(long_size.back(), 3 * short_size.back());
    EXPECT_LT(long_size.back(), 16000u);  // 40 laps x 400 returns: a tenth kept at most
    // (measured: short 718 at lap 20, 718 at lap 40; long 3,308 / 3,704 / 3,694 at laps
    // 20 / 30 / 40; max_points alone keeps every return here)
    EXPECT_LE(short_size[39], short_size[19] + short_size[19] / 20);
    EXPECT_LE(long_size[39], long_size[29] + long_size[29] / 20);
    EXPECT_EQ(longw.offered(), 16000u);
    // Still a uniform sample: the spread about the wall is the returns' (~700 and ~3,700
    // points: +-3 % and +-1 % 1-sigma), and the last lap is in it at the sample's rate (1/40).
    EXPECT_NEAR(spread(shortw), sigma, 0.1 * sigma);
    EXPECT_NEAR(spread(longw), sigma, 0.1 * sigma);
    size_t from_last_lap = 0;
    for (const float y : longw.points().getPointsBufferRef_y())
        for (const V2& p : last_lap) from_last_lap += static_cast<float>(p.y()) == y;
    const double expected = static_cast<double>(longw.size()) / 40.0;
    EXPECT_GT(static_cast<double>(from_last_lap), 0.5 * expected);
    EXPECT_LT(static_cast<double>(from_last_lap), 1.6 * expected);
}

TEST(PointsLayerTest, AreaBoundDropsPointsWhenTheAreaIsSmallerThanTheSample)
{
    // A map read from a file holds 1000 points in one 0.2 m cell: the first insert counts
    // the cells and keeps max_points_per_cell of them, chosen uniformly.
    std::stringstream ss;
    ss << "points 1000\n";
    for (int i = 0; i < 1000; ++i) ss << 0.0001 * i << ' ' << 0.05 << '\n';
    PointsLayer::Options o;
    o.max_points_per_cell = 4;
    PointsLayer layer(o);
    layer.load(ss);
    ASSERT_EQ(layer.size(), 1000u);
    layer.insertPoints({V2(0.05, 0.05)});
    EXPECT_EQ(layer.limit(), 4u);
    EXPECT_EQ(layer.size(), 4u);
    // The ones kept come from the whole sample, not its head or its tail.
    double max_x = 0;
    for (const float x : layer.points().getPointsBufferRef_x()) max_x = std::max(max_x, static_cast<double>(x));
    EXPECT_GT(max_x, 0.01);
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
