/**
 * @file outline_metrics_test.cpp
 * @brief Accuracy and coverage metrics against hand-computed values.
 */
#include "hymm/dense/outline_metrics.h"

#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>

namespace
{
using namespace hymm::dense;
using V2 = Eigen::Vector2d;

TEST(OutlineMetricsTest, MeanAndPercentileOfDistances)
{
    // Points 0.1, 0.2, ..., 2.0 m above the open segment (0,0)-(1,0).
    std::vector<V2> pts;
    for (int i = 1; i <= 20; ++i) pts.emplace_back(0.5, 0.1 * i);
    OutlineMetricsOptions o;
    o.closed = false;
    const auto m = evaluateOutlines(pts, {{V2(0, 0), V2(1, 0)}}, o);
    EXPECT_EQ(m.points, 20u);
    EXPECT_NEAR(m.mean_distance_m, 1.05, 1e-12);
    EXPECT_NEAR(m.p95_distance_m, 1.9, 1e-12);  // ceil(0.95 * 20) = 19th smallest
    // 20 samples on the segment + its end point; covered: |x - 0.5|^2 + 0.01 <= 0.09.
    EXPECT_EQ(m.outline_samples, 21u);
    EXPECT_EQ(m.covered_samples, 11u);  // x = 0.25 .. 0.75
}

TEST(OutlineMetricsTest, CoverageOfClosedSquare)
{
    // Unit square (80 samples, 20 per side); points 0.12 m below its bottom side.
    std::vector<V2> pts;
    for (int i = 0; i <= 100; ++i) pts.emplace_back(0.01 * i, -0.12);
    const Polygon square{V2(0, 0), V2(1, 0), V2(1, 1), V2(0, 1)};
    const auto m = evaluateOutlines(pts, {square});
    EXPECT_EQ(m.outline_samples, 80u);
    // bottom: 20; right side (1,0)->(1,1): y = 0, .05, .1, .15 (y + 0.12 <= 0.3): 4;
    // left side (0,1)->(0,0): y = .15, .1, .05: 3 (y = 0 belongs to the bottom side).
    EXPECT_EQ(m.covered_samples, 27u);
    EXPECT_NEAR(m.coverage, 27.0 / 80.0, 1e-12);
    EXPECT_NEAR(m.mean_distance_m, 0.12, 1e-12);
    EXPECT_THROW(evaluateOutlines(pts, {}), std::invalid_argument);
    EXPECT_TRUE(std::isnan(evaluateOutlines({}, {square}).mean_distance_m));
}

TEST(OutlineMetricsTest, OccupiedCellsAboveThreshold)
{
    mrpt::maps::COccupancyGridMap2D g;
    g.setSize(0, 1, 0, 1, 0.1f, 0.5f);
    g.setCell(3, 4, 0.95f);
    g.setCell(5, 5, 0.7f);
    const auto c = occupiedCellCentres(g, 0.8);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_NEAR(c[0].x(), 0.35, 1e-6);
    EXPECT_NEAR(c[0].y(), 0.45, 1e-6);
}

}  // namespace

namespace
{
// A trunk polygon: every vertex on the circle, the distance of a point outside it within
// 0.5% of r of the exact circle; r = 0 is the centre itself.
TEST(CirclePolygonTest, VerticesOnTheCircleAndPointForZeroRadius)
{
    const Eigen::Vector2d c(3, -2);
    const auto p = hymm::dense::circlePolygon(c, 0.4);
    ASSERT_EQ(p.size(), 32u);
    for (const auto& v : p) EXPECT_NEAR((v - c).norm(), 0.4, 1e-12);
    const auto m = hymm::dense::evaluateOutlines({c + Eigen::Vector2d(1.4, 0.3)}, {p});
    EXPECT_NEAR(m.mean_distance_m, std::hypot(1.4, 0.3) - 0.4, 0.005 * 0.4);
    const auto z = hymm::dense::circlePolygon(c, 0);
    ASSERT_EQ(z.size(), 2u);
    EXPECT_NEAR(hymm::dense::evaluateOutlines({c + Eigen::Vector2d(0, 2)}, {z}).mean_distance_m, 2.0, 1e-12);
}
}  // namespace
