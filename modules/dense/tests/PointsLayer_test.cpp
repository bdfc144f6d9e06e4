/**
 * @file PointsLayer_test.cpp
 * @brief Raw points stored in reference coordinates, thinned, rendered, serialised.
 */
#include "hymm/dense/PointsLayer.h"

#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

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
