#include <gtest/gtest.h>
#include <hymm/sim/ClosedPath.h>
#include <hymm/sim/World.h>
#include <hymm/sim/geometry.h>

#include <cmath>

namespace
{
using hymm::sim::Polygon;
using hymm::sim::Vec2;

const Polygon kSquare = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};  // 2 m square

TEST(GeometryTest, RayHitsCircleFromOutsideAtTheNearSide)
{
    const auto t = hymm::sim::rayCircle({0, 0}, {1, 0}, {10, 0}, 1.0);
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 9.0, 1e-12);
    // Off-centre: the chord at height 0.6 of a unit circle enters at x = 10 - 0.8.
    const auto t2 = hymm::sim::rayCircle({0, 0.6}, {1, 0}, {10, 0}, 1.0);
    ASSERT_TRUE(t2);
    EXPECT_NEAR(*t2, 9.2, 1e-12);
}

TEST(GeometryTest, RayMissesCircleBesideOrBehind)
{
    EXPECT_FALSE(hymm::sim::rayCircle({0, 0}, {1, 0}, {10, 1.5}, 1.0));  // passes beside
    EXPECT_FALSE(hymm::sim::rayCircle({0, 0}, {-1, 0}, {10, 0}, 1.0));   // behind the ray
}

TEST(GeometryTest, RayFromInsideCircleHitsTheExit)
{
    const auto t = hymm::sim::rayCircle({10.5, 0}, {1, 0}, {10, 0}, 1.0);
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 0.5, 1e-12);
}

TEST(GeometryTest, RayHitsSegmentInsideItsEndsOnly)
{
    const auto t = hymm::sim::raySegment({0, 0}, {1, 0}, {5, -1}, {5, 1});
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 5.0, 1e-12);
    EXPECT_FALSE(hymm::sim::raySegment({0, 0}, {1, 0}, {5, 0.5}, {5, 1}));  // above the ray
    EXPECT_FALSE(hymm::sim::raySegment({0, 0}, {-1, 0}, {5, -1}, {5, 1}));  // behind
    EXPECT_FALSE(hymm::sim::raySegment({0, 0}, {1, 0}, {2, 0}, {4, 0}));    // collinear
    // Diagonal ray at 45 degrees to a vertical wall at x = 3.
    const Vec2 d(std::sqrt(0.5), std::sqrt(0.5));
    const auto t2 = hymm::sim::raySegment({0, 0}, d, {3, -10}, {3, 10});
    ASSERT_TRUE(t2);
    EXPECT_NEAR(*t2, 3 * std::sqrt(2.0), 1e-12);
}

TEST(GeometryTest, RayReturnsTheNearestPolygonEdge)
{
    // From the left, the ray crosses x = 0 then x = 2: the first is the hit.
    const auto t = hymm::sim::rayPolygon({-3, 1}, {1, 0}, kSquare);
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 3.0, 1e-12);
    // From inside, the exit edge.
    const auto t_in = hymm::sim::rayPolygon({0.5, 1}, {0, 1}, kSquare);
    ASSERT_TRUE(t_in);
    EXPECT_NEAR(*t_in, 1.0, 1e-12);
    EXPECT_FALSE(hymm::sim::rayPolygon({-3, 3}, {1, 0}, kSquare));
}

TEST(GeometryTest, PolygonDistancesAndContainment)
{
    EXPECT_TRUE(hymm::sim::pointInPolygon({1, 1}, kSquare));
    EXPECT_FALSE(hymm::sim::pointInPolygon({3, 1}, kSquare));
    EXPECT_DOUBLE_EQ(hymm::sim::pointPolygonDistance({1, 1}, kSquare), 0.0);
    EXPECT_NEAR(hymm::sim::pointPolygonDistance({5, 6}, kSquare), 5.0, 1e-12);  // to (2, 2)
    const Polygon far = hymm::sim::transformPolygon(kSquare, 5, 0, 0);
    EXPECT_NEAR(hymm::sim::polygonDistance(kSquare, far), 3.0, 1e-12);
    const Polygon inner = {{0.5, 0.5}, {1, 0.5}, {1, 1}};
    EXPECT_DOUBLE_EQ(hymm::sim::polygonDistance(kSquare, inner), 0.0);  // contained
    EXPECT_GT(hymm::sim::boundaryDistance(kSquare, inner), 0.4);        // edges apart
    EXPECT_NEAR(hymm::sim::signedArea(kSquare), 4.0, 1e-12);
}

TEST(WorldSnapshotTest, NearestHitAmongLandmarksAndObjectsWithinMaxRange)
{
    hymm::sim::WorldSnapshot snap;
    snap.landmarks.push_back({7, {10, 0}, 0.5});
    snap.objects.emplace_back(3, hymm::sim::transformPolygon(kSquare, 5, -1, 0));  // x in [5, 7]
    auto hit = snap.castRay({0, 0}, 0.0, 50);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->range, 5.0, 1e-12);
    EXPECT_FALSE(hit->landmark);
    EXPECT_EQ(hit->id, 3);
    // Looking up, nothing: no return.
    EXPECT_FALSE(snap.castRay({0, 0}, M_PI / 2, 50));
    // Max range shorter than the nearest hit: no return.
    EXPECT_FALSE(snap.castRay({0, 0}, 0.0, 4.99));
    // From x = 8 the landmark's trunk is the first thing ahead; skipping it, nothing.
    hit = snap.castRay({8, 0}, 0.0, 50);
    ASSERT_TRUE(hit);
    EXPECT_TRUE(hit->landmark);
    EXPECT_EQ(hit->id, 7);
    EXPECT_NEAR(hit->range, 1.5, 1e-12);
    EXPECT_FALSE(snap.castRay({8, 0}, 0.0, 50, 7));
}

TEST(ClosedPathTest, RoundedRectangleHasTheAnalyticLength)
{
    // 40 x 20 rectangle with corners of radius 5: 2 (40 + 20) - 8 r + 2 pi r, up to the
    // chords of the discretised arcs.
    const hymm::sim::ClosedPath path({{0, 0}, {20, 0}, {20, 20}, {-20, 20}, {-20, 0}}, 5.0);
    const double exact = 120 - 40 + 2 * M_PI * 5;
    EXPECT_NEAR(path.length(), exact, 0.02);
    EXPECT_LT(path.length(), exact);
    EXPECT_NEAR(path.pointAt(0).norm(), 0.0, 1e-12);
    EXPECT_NEAR(path.headingAt(0), 0.0, 1e-12);
    // The middle of the top side, half a loop from the start.
    EXPECT_NEAR((path.pointAt(path.length() / 2) - Vec2(0, 20)).norm(), 0.0, 1e-9);
    // Progress keeps growing across the start line.
    const double s = path.project(path.pointAt(1.0), path.length() - 0.5, 2, 5);
    EXPECT_NEAR(s, path.length() + 1.0, 1e-9);
}

TEST(ClosedPathTest, RejectsDegenerateLoops)
{
    EXPECT_THROW(hymm::sim::ClosedPath({{0, 0}, {1, 0}}, 0), std::invalid_argument);
    EXPECT_THROW(hymm::sim::ClosedPath({{0, 0}, {1, 0}, {1, 0}}, 0), std::invalid_argument);
    EXPECT_THROW(hymm::sim::ClosedPath({{0, 0}, {10, 0}, {0, 0.01}}, 0), std::invalid_argument);
}

}  // namespace
