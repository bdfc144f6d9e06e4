/**
 * @file ClassicOccupancyGrid_test.cpp
 * @brief The baseline places content at the pose estimate of observation time.
 */
#include "hymm/dense/ClassicOccupancyGrid.h"

#include "hymm/dense/outline_metrics.h"
#include "synthetic_partition.h"

#include <gtest/gtest.h>

#include <cmath>

namespace
{
using namespace hymm::dense;
using V2 = Eigen::Vector2d;

ClassicOccupancyGrid::Options area()
{
    ClassicOccupancyGrid::Options o;
    o.x_min_m = -5;
    o.x_max_m = 25;
    o.y_min_m = -5;
    o.y_max_m = 20;
    return o;
}

std::vector<V2> occupied(const ClassicOccupancyGrid& g)
{
    mrpt::maps::COccupancyGridMap2D og;
    g.toOccupancyGridMap(og);
    return occupiedCellCentres(og, 0.8);
}

TEST(ClassicOccupancyGridTest, WallAppearsWhereThePoseEstimatePutsIt)
{
    const mrpt::math::TPose2D truth{3.0, 7.5, 0.0};
    const ScanPoints scan = synthetic::wallScan(truth, {0.3, 0, 0}, 17.0, 161, 40.0 * M_PI / 180.0);
    OccupancyLayer::Options model;
    model.cell_size_m = 0.1;

    ClassicOccupancyGrid right(area(), model), wrong(area(), model);
    const mrpt::math::TPose2D estimate{4.0, 7.5, 0.0};  // 1 m error at observation time
    for (int k = 0; k < 3; ++k)
    {
        right.insertScan(scan, truth);
        wrong.insertScan(scan, estimate);
    }
    const auto occ_right = occupied(right), occ_wrong = occupied(wrong);
    ASSERT_GT(occ_right.size(), 50u);
    ASSERT_GT(occ_wrong.size(), 50u);
    for (const V2& c : occ_right) EXPECT_LE(std::abs(c.x() - 17.0), 0.1 + 1e-6);
    for (const V2& c : occ_wrong) EXPECT_LE(std::abs(c.x() - 18.0), 0.1 + 1e-6);  // displaced
    EXPECT_LT(right.probabilityAt(V2(10, 7.5)), 0.3);
    EXPECT_NEAR(right.probabilityAt(V2(20, 7.5)), 0.5, 1e-6);  // behind the wall: unknown
    // The free space of the wrong insertion runs through the true wall.
    EXPECT_LT(wrong.probabilityAt(V2(17.0, 7.5)), 0.3);
}

TEST(ClassicOccupancyGridTest, BeamsLeavingTheAreaAreClipped)
{
    ClassicOccupancyGrid::Options o = area();
    o.x_max_m = 10;
    OccupancyLayer::Options model;
    model.cell_size_m = 0.5;
    ClassicOccupancyGrid g(o, model);
    ScanPoints s;
    s.points = {V2(20, 0)};
    g.insertScan(s, {0, 0, 0});
    EXPECT_LT(g.probabilityAt(V2(9.9, 0.1)), 0.45);
    EXPECT_THROW(ClassicOccupancyGrid([] {
        auto b = area();
        b.x_max_m = b.x_min_m;
        return b;
    }(), model), std::invalid_argument);
}

}  // namespace
