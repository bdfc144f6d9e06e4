/**
 * @file OccupancyCoarsen_test.cpp
 * @brief Per-region resolution (Sec. 4.1.3, Fig. 4.6): an almost-empty region is
 *        re-sampled to the coarse cell size, uses less memory and keeps its occupied
 *        cells; a region with structure is left alone.
 */
#include "hymm/dense/OccupancyLayer.h"

#include <gtest/gtest.h>

#include <sstream>

namespace
{
using namespace hymm::dense;
using V2 = Eigen::Vector2d;
const hymm::ltr::TriangleFrame::Vertices kRef{{V2(0, 0), V2(4, 0), V2(0, 4)}};

OccupancyLayer::Options opts()
{
    OccupancyLayer::Options o;
    o.cell_size_m = 0.1;
    o.coarse_cell_size_m = 0.5;  // thesis: 0.2 -> 0.5 m; cellsPercent 0.99, minProb 0.2
    return o;
}

/** Horizontal free rays over every row of cells (no returns). */
RegionScan sweep()
{
    RegionScan s;
    s.sensor = V2(-0.5, 0);
    for (double y = 0.02; y < 4.0; y += 0.05) s.rays.push_back({V2(-0.5, y), V2(4.5, y), false});
    return s;
}

RegionScan hitsAt(const std::vector<V2>& pts)
{
    RegionScan s;
    s.sensor = V2(-0.5, 0);
    for (const V2& p : pts) s.rays.push_back({V2(p.x() - 0.01, p.y()), p, true});  // the hit cell only
    return s;
}

TEST(OccupancyCoarsenTest, AlmostEmptyRegionIsCoarsenedAndKeepsItsObstacle)
{
    OccupancyLayer layer(opts(), kRef);
    for (int k = 0; k < 6; ++k) layer.insert(sweep());  // 6 misses: P = 0.08 < minProb
    for (int k = 0; k < 6; ++k) layer.insert(hitsAt({V2(1.05, 1.05)}));
    ASSERT_GT(layer.probabilityAt(V2(1.05, 1.05)), 0.9);
    ASSERT_GT(layer.freeFraction(0.2), 0.99);
    const size_t before = layer.memoryBytes();
    EXPECT_FALSE(layer.isCoarse());
    ASSERT_TRUE(layer.coarsen());
    EXPECT_TRUE(layer.isCoarse());
    EXPECT_DOUBLE_EQ(layer.grid().cellSize(), 0.5);
    EXPECT_LT(layer.memoryBytes() * 10, before);  // 25x fewer cells
    // The obstacle survives in its coarse cell [1, 1.5)^2; free space stays free.
    EXPECT_GT(layer.probabilityAt(V2(1.05, 1.05)), 0.9);
    EXPECT_GT(layer.probabilityAt(V2(1.45, 1.45)), 0.9);
    EXPECT_LT(layer.probabilityAt(V2(2.2, 0.7)), 0.2);
    EXPECT_LT(layer.probabilityAt(V2(0.3, 3.2)), 0.2);
    EXPECT_FALSE(layer.coarsen());  // already coarse

    // Later scans update the coarse grid; the coarse size survives save / load.
    for (int k = 0; k < 4; ++k) layer.insert(hitsAt({V2(2.7, 0.7)}));
    EXPECT_GT(layer.probabilityAt(V2(2.6, 0.6)), 0.5);
    std::stringstream ss;
    layer.save(ss);
    OccupancyLayer copy(opts(), kRef);
    copy.load(ss);
    EXPECT_TRUE(copy.isCoarse());
    EXPECT_EQ(copy.probabilityAt(V2(1.05, 1.05)), layer.probabilityAt(V2(1.05, 1.05)));
}

TEST(OccupancyCoarsenTest, RegionsWithStructureOrUnknownCellsStayFine)
{
    // A wall of 40 occupied cells: ~5% of the triangle's cells are not free.
    OccupancyLayer wall(opts(), kRef);
    for (int k = 0; k < 6; ++k) wall.insert(sweep());
    std::vector<V2> pts;
    for (double y = 0.05; y < 3.9; y += 0.1) pts.emplace_back(0.05, y);
    for (int k = 0; k < 3; ++k) wall.insert(hitsAt(pts));
    EXPECT_LT(wall.freeFraction(0.2), 0.99);
    EXPECT_FALSE(wall.coarsen());
    EXPECT_DOUBLE_EQ(wall.grid().cellSize(), 0.1);

    // Never observed: unknown (0.5) is not empty.
    OccupancyLayer unseen(opts(), kRef);
    EXPECT_FALSE(unseen.coarsen());

    // Coarsening off.
    auto o = opts();
    o.coarse_cell_size_m = 0;
    OccupancyLayer off(o, kRef);
    for (int k = 0; k < 6; ++k) off.insert(sweep());
    EXPECT_FALSE(off.coarsen());
}

}  // namespace
