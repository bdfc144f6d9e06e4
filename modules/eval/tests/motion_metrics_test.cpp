#include <gtest/gtest.h>
#include <hymm/eval/motion_metrics.h>

#include <stdexcept>

namespace
{
using hymm::eval::CellMask;

TEST(MotionMetrics, RasterisesAndScoresWithTolerance)
{
    CellMask truth(Eigen::Vector2d(0, 0), 0.1, 100, 100);
    truth.fillPolygon({{2, 2}, {4, 2}, {4, 3}, {2, 3}});
    EXPECT_EQ(truth.count(), 200u);
    CellMask outline(Eigen::Vector2d(0, 0), 0.1, 100, 100);
    outline.markOutline({{2, 2}, {4, 2}, {4, 3}, {2, 3}}, 0.051);
    // The cells either side of each edge; the four inner corner cells are shared.
    EXPECT_EQ(outline.count(), 2u * 40u + 2u * 20u - 4u);

    CellMask det = CellMask(truth.origin, truth.cell, truth.nx, truth.ny);
    for (int ix = 20; ix < 40; ++ix) det.set(ix, 19);  // one row just below the box
    for (int ix = 80; ix < 90; ++ix) det.set(ix, 80);  // far off
    const auto exact = hymm::eval::scoreDetection(det, truth, 0);
    EXPECT_EQ(exact.detected, 30u);
    EXPECT_EQ(exact.detected_correct, 0u);
    const auto tol = hymm::eval::scoreDetection(det, truth, 1);
    EXPECT_EQ(tol.detected_correct, 20u);
    EXPECT_NEAR(tol.precision, 20.0 / 30.0, 1e-12);
    EXPECT_EQ(tol.truth_found, 20u);  // the bottom row of the box
    EXPECT_EQ(hymm::eval::countNear(det, truth, 1), 20u);
    EXPECT_THROW(det.intersect(CellMask(truth.origin, 0.2, 50, 50)), std::invalid_argument);
}

TEST(MotionMetrics, FromGridReadsTheOccupiedCells)
{
    mrpt::maps::COccupancyGridMap2D g(-1.0f, 1.0f, -1.0f, 1.0f, 0.1f);
    g.setPos(0.55f, -0.35f, 1.0f);
    const auto m = CellMask::fromGrid(g, 0.9f);
    EXPECT_EQ(m.count(), 1u);
    int ix, iy;
    ASSERT_TRUE(m.cellOf(Eigen::Vector2d(0.55, -0.35), ix, iy));
    EXPECT_TRUE(m.get(ix, iy));
}

}  // namespace
