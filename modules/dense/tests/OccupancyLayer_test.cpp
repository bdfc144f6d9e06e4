/**
 * @file OccupancyLayer_test.cpp
 * @brief A region's grid stays inside its triangle; rendering through the affine map.
 */
#include "hymm/dense/OccupancyLayer.h"

#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>

#include <cmath>
#include <sstream>

namespace
{
using namespace hymm::dense;
using V2 = Eigen::Vector2d;
const hymm::ltr::TriangleFrame::Vertices kRef{{V2(0, 0), V2(4, 0), V2(0, 4)}};

OccupancyLayer::Options opts()
{
    OccupancyLayer::Options o;
    o.cell_size_m = 0.25;
    return o;
}

/** Rays that sweep the whole bounding box, some ending in returns outside the triangle. */
RegionScan sweepingScan()
{
    RegionScan s;
    s.sensor = V2(-1, -1);
    for (int k = 0; k <= 60; ++k)
    {
        const double a = M_PI / 2 * k / 60.0;
        s.rays.push_back({s.sensor, s.sensor + 7.0 * V2(std::cos(a), std::sin(a)), true});
    }
    return s;
}

TEST(OccupancyLayerTest, CellsOutsideTriangleAreNeverUpdated)
{
    OccupancyLayer layer(opts(), kRef);
    const LogOddsGrid& g = layer.grid();
    ASSERT_EQ(g.sizeX(), 16);
    ASSERT_EQ(g.sizeY(), 16);
    for (int k = 0; k < 3; ++k) layer.insert(sweepingScan());
    size_t changed_inside = 0;
    for (int ix = 0; ix < g.sizeX(); ++ix)
        for (int iy = 0; iy < g.sizeY(); ++iy)
        {
            // The cell square [x0, x0 + h] x [y0, y0 + h] meets x, y >= 0, x + y <= 4 iff x0 + y0 <= 4.
            const V2 c = g.cellMin(ix, iy);
            const bool meets = c.x() + c.y() <= 4.0 + 1e-12;
            EXPECT_EQ(g.updatable(ix, iy), meets) << ix << "," << iy;
            if (!meets)
                EXPECT_EQ(g.logOdds(ix, iy), g.initialLogOdds()) << ix << "," << iy;
            else if (g.logOdds(ix, iy) != g.initialLogOdds())
                ++changed_inside;
        }
    // Every cell the sweep crosses inside the triangle was freed (the rays cover it densely).
    EXPECT_GT(changed_inside, 100u);
    EXPECT_LT(layer.probabilityAt(V2(1, 1)), 0.3);
}

TEST(OccupancyLayerTest, ReturnMarksItsCellOccupiedAndCellsBeforeItFree)
{
    OccupancyLayer layer(opts(), kRef);
    RegionScan s;
    s.rays.push_back({V2(0.1, 0.1), V2(2.1, 0.1), true});
    layer.insert(s);
    EXPECT_NEAR(layer.probabilityAt(V2(2.1, 0.1)), 0.7, 1e-6);
    EXPECT_NEAR(layer.probabilityAt(V2(1.0, 0.1)), 0.4, 1e-6);
    EXPECT_NEAR(layer.probabilityAt(V2(3.0, 0.1)), 0.5, 1e-6);
    EXPECT_NEAR(layer.probabilityAt(V2(1.0, 1.0)), 0.5, 1e-6);
    EXPECT_EQ(layer.size(), 9u);  // cells 0..7 free, cell 8 occupied
}

TEST(OccupancyLayerTest, RendersIntoCurrentTriangleThroughAffineMap)
{
    OccupancyLayer layer(opts(), kRef);
    RegionScan s;
    s.rays.push_back({V2(0.1, 0.1), V2(2.1, 0.1), true});
    for (int k = 0; k < 3; ++k) layer.insert(s);
    // Current triangle: reference scaled by 2 and shifted by (10, 5).
    const hymm::ltr::TriangleFrame ref(kRef);
    const hymm::ltr::TriangleFrame cur(V2(10, 5), V2(18, 5), V2(10, 13));
    const hymm::ltr::AffineRegionMap map(ref, cur);
    mrpt::maps::COccupancyGridMap2D og;
    og.setSize(9, 19, 4, 14, 0.1f, 0.5f);
    layer.renderInto(map, og);
    // The return at ref (2.1, 0.1) is at (14.2, 5.2) now.
    EXPECT_GT(og.getPos(14.2f, 5.2f), 0.8f);
    EXPECT_LT(og.getPos(12.0f, 5.2f), 0.3f);
    EXPECT_NEAR(og.getPos(9.5f, 5.2f), 0.5f, 0.01f);   // left of the triangle: untouched
    EXPECT_NEAR(og.getPos(16.0f, 12.0f), 0.5f, 0.01f); // beyond the hypotenuse
    mrpt::maps::CSimplePointsMap wrong;
    EXPECT_THROW(layer.renderInto(map, wrong), std::invalid_argument);
}

TEST(OccupancyLayerTest, SaveLoadRoundTrip)
{
    OccupancyLayer a(opts(), kRef);
    a.insert(sweepingScan());
    std::stringstream ss;
    a.save(ss);
    OccupancyLayer b(opts(), kRef);
    b.load(ss);
    std::stringstream s1, s2;
    a.save(s1);
    b.save(s2);
    EXPECT_EQ(s1.str(), s2.str());
    EXPECT_EQ(b.size(), a.size());
}

}  // namespace
