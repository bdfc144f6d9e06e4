/**
 * @file geometry_test.cpp
 * @brief Segment clipping and box/triangle tests against hand-computed values.
 */
#include "hymm/dense/geometry.h"

#include <gtest/gtest.h>

namespace
{
using namespace hymm::dense;
using V2 = Eigen::Vector2d;
const std::array<V2, 3> kTri{{V2(0, 0), V2(4, 0), V2(0, 4)}};

TEST(GeometryTest, ClipsSegmentCrossingTriangle)
{
    // y = 1 from x = -2 to x = 6 enters at x = 0 (t = 0.25), leaves at x + y = 4 (x = 3, t = 0.625).
    const auto iv = clipSegmentToTriangle(V2(-2, 1), V2(6, 1), kTri, 0.0);
    ASSERT_TRUE(iv);
    EXPECT_NEAR(iv->t0, 0.25, 1e-12);
    EXPECT_NEAR(iv->t1, 0.625, 1e-12);
    // Clockwise vertex order gives the same interval.
    const auto cw = clipSegmentToTriangle(V2(-2, 1), V2(6, 1), {{kTri[0], kTri[2], kTri[1]}}, 0.0);
    ASSERT_TRUE(cw);
    EXPECT_NEAR(cw->t0, 0.25, 1e-12);
    EXPECT_NEAR(cw->t1, 0.625, 1e-12);
}

TEST(GeometryTest, SegmentInsideIsKeptWholeAndOutsideIsRejected)
{
    const auto in = clipSegmentToTriangle(V2(0.5, 0.5), V2(1, 2), kTri);
    ASSERT_TRUE(in);
    EXPECT_DOUBLE_EQ(in->t0, 0.0);
    EXPECT_DOUBLE_EQ(in->t1, 1.0);
    EXPECT_FALSE(clipSegmentToTriangle(V2(3, 3), V2(5, 1), kTri));
    EXPECT_FALSE(clipSegmentToTriangle(V2(-1, -1), V2(-1, 5), kTri));
}

TEST(GeometryTest, ClipsSegmentToBox)
{
    const auto iv = clipSegmentToBox(V2(-1, 0.5), V2(3, 0.5), V2(0, 0), V2(1, 1));
    ASSERT_TRUE(iv);
    EXPECT_NEAR(iv->t0, 0.25, 1e-12);
    EXPECT_NEAR(iv->t1, 0.5, 1e-12);
    EXPECT_FALSE(clipSegmentToBox(V2(-1, 2), V2(3, 2), V2(0, 0), V2(1, 1)));
}

TEST(GeometryTest, BoxTriangleIntersection)
{
    EXPECT_TRUE(boxIntersectsTriangle(V2(1, 1), V2(1.5, 1.5), kTri));     // inside
    EXPECT_TRUE(boxIntersectsTriangle(V2(1.9, 1.9), V2(2.5, 2.5), kTri));  // straddles hypotenuse
    EXPECT_FALSE(boxIntersectsTriangle(V2(2.1, 2.1), V2(2.5, 2.5), kTri)); // beyond it (x+y > 4)
    EXPECT_FALSE(boxIntersectsTriangle(V2(-2, -2), V2(-1, -1), kTri));
    EXPECT_TRUE(boxIntersectsTriangle(V2(-1, -1), V2(5, 5), kTri));       // contains it
}

TEST(GeometryTest, ContainmentAndSegmentDistance)
{
    EXPECT_TRUE(triangleContains(kTri, V2(2, 2)));  // on the hypotenuse
    EXPECT_FALSE(triangleContains(kTri, V2(2.01, 2)));
    EXPECT_DOUBLE_EQ(distanceToSegment(V2(1, 1), V2(0, 0), V2(2, 0)), 1.0);
    EXPECT_DOUBLE_EQ(distanceToSegment(V2(3, 4), V2(-1, 0), V2(0, 0)), 5.0);
}

}  // namespace
