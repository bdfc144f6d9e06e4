/**
 * @file laser_coverage_test.cpp
 * @brief "What the laser saw": scans placed at the true poses mark the outline part they
 *        hit; coverage of that part; sampling identical to dense::evaluateOutlines.
 */
#include "hymm/eval/laser_coverage.h"

#include <gtest/gtest.h>
#include <hymm/ltr/DenseCovarianceView.h>
#include <hymm/ltr/VirtualLandmarks.h>

#include <cmath>
#include <random>

namespace
{
using namespace hymm::eval;
using V2 = Eigen::Vector2d;

/** A 10 x 2 m box with its lower left corner at the origin. */
std::vector<hymm::dense::Polygon> box() { return {{V2(0, 0), V2(10, 0), V2(10, 2), V2(0, 2)}}; }

/** Returns in the frame of a sensor at global pose `s` (x, y, phi) for global points. */
std::vector<V2> inSensorFrame(const Eigen::Vector3d& s, const std::vector<V2>& global)
{
    std::vector<V2> out;
    const double c = std::cos(s.z()), sn = std::sin(s.z());
    for (const V2& g : global)
    {
        const V2 d = g - s.head<2>();
        out.emplace_back(c * d.x() + sn * d.y(), -sn * d.x() + c * d.y());
    }
    return out;
}

/** Points along the bottom edge (y = 0) for x in [x0, x1], every 0.1 m. */
std::vector<V2> bottomEdge(double x0, double x1)
{
    std::vector<V2> out;
    for (double x = x0; x <= x1 + 1e-9; x += 0.1) out.emplace_back(x, 0.0);
    return out;
}

hymm::io::StampedPose2D pose(double t, double x, double y, double phi) { return {t, x, y, phi}; }

TEST(LaserCoverageTest, SeenPartIsWhereTheReturnsHitAtTheTruePose)
{
    // Vehicle at (5, -5) facing +y sees x in [3, 7] of the bottom edge.
    const Eigen::Vector3d truth(5, -5, M_PI / 2);
    TimedScan s;
    s.t = 10.0;
    s.scan.points = inSensorFrame(truth, bottomEdge(3, 7));
    const SeenOutline seen =
        laserSeenOutline({s}, {pose(9.65, 0, 0, 0), pose(10.0, 5, -5, M_PI / 2)}, box());

    EXPECT_EQ(seen.returns.scans_placed, 1u);
    EXPECT_EQ(seen.returns.scans_unmatched, 0u);
    EXPECT_EQ(seen.samples.points.size(), 480u);  // 24 m of outline every 0.05 m
    size_t expected = 0;
    for (size_t i = 0; i < seen.samples.points.size(); ++i)
    {
        const V2& q = seen.samples.points[i];
        const bool on_seen_part =
            std::abs(q.y()) < 1e-12 && q.x() >= 3.0 - 1e-9 && q.x() <= 7.0 + 1e-9;
        expected += on_seen_part;
        if (on_seen_part)
        {
            EXPECT_TRUE(seen.seen[i]) << q.transpose();
        }
        // Nothing farther than the radius from the hit stretch is seen.
        if (seen.seen[i])
        {
            EXPECT_TRUE(std::abs(q.y()) < 0.3 && q.x() > 2.7 - 1e-9 && q.x() < 7.3 + 1e-9)
                << q.transpose();
        }
    }
    EXPECT_EQ(expected, 81u);
    EXPECT_GE(seen.seen_samples, expected);
    EXPECT_LE(seen.seen_samples, expected + 12);  // + up to 0.3 m beyond each end
    EXPECT_NEAR(seen.seenFraction(), static_cast<double>(seen.seen_samples) / 480.0, 1e-15);
}

TEST(LaserCoverageTest, ScansArePlacedAtTheTruePoseOfTheirTimestampWithTheirMounting)
{
    // The same sensor-frame returns hit the bottom edge from the first true pose and the
    // top edge from the second (mirror image); a third scan has no true pose in time.
    const Eigen::Vector3d below(5, -5, M_PI / 2), above(5, 7, -M_PI / 2);
    TimedScan a, b, lost;
    a.t = 1.0;
    // Returns between the 0.05 m samples, so no sample sits at exactly the radius.
    a.scan.points = inSensorFrame(below, bottomEdge(4.025, 6.025));
    b = a;
    b.t = 2.0;
    lost = a;
    lost.t = 5.0;
    const std::vector<hymm::io::StampedPose2D> truth{pose(2.0, above.x(), above.y(), above.z()),
                                                       pose(1.0, below.x(), below.y(), below.z())};
    const SeenOutline seen = laserSeenOutline({a, b, lost}, truth, box());
    EXPECT_EQ(seen.returns.scans_placed, 2u);
    EXPECT_EQ(seen.returns.scans_unmatched, 1u);
    size_t top = 0, bottom = 0;
    for (size_t i = 0; i < seen.samples.points.size(); ++i)
        if (seen.seen[i]) (seen.samples.points[i].y() > 1 ? top : bottom)++;
    EXPECT_GE(bottom, 41u);
    EXPECT_EQ(top, bottom);

    // A sensor mounted 1 m ahead on the vehicle: the same returns land 1 m farther.
    TimedScan m = a;
    m.scan.sensor_on_vehicle = mrpt::math::TPose2D(1.0, 0.0, 0.0);
    const PlacedReturns placed = placeAtTruePoses({m}, truth);
    ASSERT_EQ(placed.points.size(), a.scan.points.size());
    for (const V2& p : placed.points) EXPECT_NEAR(p.y(), 1.0, 1e-9);
}

TEST(LaserCoverageTest, ReturnsBeyondMaxRangeAreNotSeen)
{
    const Eigen::Vector3d truth(5, -5, M_PI / 2);
    TimedScan s;
    s.t = 0;
    s.scan.points = inSensorFrame(truth, bottomEdge(0, 10));  // ranges 5 .. 7.07 m
    LaserCoverageOptions o;
    o.max_range_m = 5.5;
    const SeenOutline seen = laserSeenOutline({s}, {pose(0, 5, -5, M_PI / 2)}, box(), o);
    // Kept: |x - 5| <= sqrt(5.5^2 - 25) = 2.29 m.
    EXPECT_EQ(seen.returns.beyond_range + seen.returns.points.size(), s.scan.points.size());
    EXPECT_GT(seen.returns.beyond_range, 0u);
    for (size_t i = 0; i < seen.samples.points.size(); ++i)
        if (seen.seen[i])
        {
            EXPECT_LT(std::abs(seen.samples.points[i].x() - 5.0), 2.29 + 0.3 + 1e-9);
        }
}

TEST(LaserCoverageTest, CoverageOfTheSeenPartCountsOnlySeenSamples)
{
    const Eigen::Vector3d truth(5, -5, M_PI / 2);
    TimedScan s;
    s.scan.points = inSensorFrame(truth, bottomEdge(2, 8));
    const SeenOutline seen = laserSeenOutline({s}, {pose(0, 5, -5, M_PI / 2)}, box());
    // A map covering the left half of the seen stretch and part of the unseen top edge.
    std::vector<V2> map = bottomEdge(2, 4.7);  // seen: [1.7, 8.3]; covered: [1.7, 5.0]
    for (double x = 1; x <= 9; x += 0.1) map.emplace_back(x, 2.0);
    const SeenCoverage c = coverageOfSeen(seen, map);
    EXPECT_EQ(c.seen_samples, seen.seen_samples);
    EXPECT_NEAR(c.seen_coverage, 0.5, 0.03);
    size_t both = 0;
    for (size_t i = 0; i < c.samples; ++i) both += seen.seen[i] && c.covered[i];
    EXPECT_EQ(both, c.covered_seen_samples);
    EXPECT_GT(c.covered_samples, c.covered_seen_samples);  // the top edge counts overall only
    EXPECT_NEAR(c.coverage, static_cast<double>(c.covered_samples) / static_cast<double>(c.samples),
                1e-15);
    EXPECT_DOUBLE_EQ(coverageOfSeen(seen, {}).seen_coverage, 0.0);
}

TEST(LaserCoverageTest, OverallCoverageEqualsTheDenseOutlineMetric)
{
    // Random closed and open outlines and points: same samples, same covered count.
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-10, 10);
    for (const bool closed : {true, false})
    {
        std::vector<hymm::dense::Polygon> outlines(5);
        for (auto& p : outlines)
            for (int k = 0; k < 4; ++k) p.emplace_back(u(rng), u(rng));
        std::vector<V2> pts;
        for (int i = 0; i < 3000; ++i) pts.emplace_back(u(rng), u(rng));
        LaserCoverageOptions o;
        o.closed = closed;
        const SeenOutline seen = laserSeenOutline({}, {pose(0, 0, 0, 0)}, outlines, o);
        EXPECT_EQ(seen.seen_samples, 0u);
        hymm::dense::OutlineMetricsOptions mo;
        mo.closed = closed;
        const auto ref = hymm::dense::evaluateOutlines(pts, outlines, mo);
        const SeenCoverage c = coverageOfSeen(seen, pts);
        EXPECT_EQ(c.samples, ref.outline_samples);
        EXPECT_EQ(c.covered_samples, ref.covered_samples);
    }
}

TEST(LaserCoverageTest, BadInputIsRejected)
{
    EXPECT_THROW(laserSeenOutline({}, {}, box()), std::invalid_argument);
    EXPECT_THROW(laserSeenOutline({}, {pose(0, 0, 0, 0)}, {}), std::invalid_argument);
    LaserCoverageOptions o;
    o.radius_m = 0;
    EXPECT_THROW(laserSeenOutline({}, {pose(0, 0, 0, 0)}, box(), o), std::invalid_argument);
    o = LaserCoverageOptions();
    o.time_tolerance_s = -1;
    EXPECT_THROW(placeAtTruePoses({}, {pose(0, 0, 0, 0)}, o), std::invalid_argument);
    EXPECT_THROW(sampleOutlines(box(), 0.0, true), std::invalid_argument);
}

/** A filter view of `lms` (ids 100, 101, ...) with a strong common error, so every
 *  triple passes the correlation condition. */
hymm::ltr::DenseCovarianceView view(const std::vector<V2>& lms)
{
    const int n = 3 + 2 * static_cast<int>(lms.size());
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(n);
    Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, 2);
    std::map<long, int> offsets;
    g.topRows<2>().setIdentity();
    for (size_t i = 0; i < lms.size(); ++i)
    {
        const int o = 3 + 2 * static_cast<int>(i);
        offsets[100 + static_cast<long>(i)] = o;
        mean.segment<2>(o) = lms[i];
        g.block<2, 2>(o, 0).setIdentity();
    }
    Eigen::MatrixXd cov = g * g.transpose();
    cov.diagonal().array() += 1e-4;
    return hymm::ltr::DenseCovarianceView(mean, cov, offsets, 0);
}

TEST(LaserCoverageTest, RegionsAreDrawnOnTheTrueVerticesOfTheirLandmarks)
{
    // Estimated landmarks 100..102 are the true ones shifted by (1, -2) and the map is
    // off by that much; drawn on the true vertices, its points return to the truth.
    const std::vector<V2> truth{V2(0, 0), V2(10, 0), V2(0, 10)};
    const V2 drift(1, -2);
    std::vector<V2> est;
    for (const V2& t : truth) est.push_back(t + drift);
    hymm::ltr::RegionPartition part{hymm::ltr::RegionPartition::Options()};
    long rid = -1;
    ASSERT_TRUE(part.tryAddRegion({100, 101, 102}, view(est), 0.0, &rid).accepted());
    hymm::dense::HybridMetricMap::Options mo;
    mo.enable_occupancy = false;
    hymm::dense::HybridMetricMap map(mo);
    hymm::dense::RegionScan rs;
    rs.hits = {V2(2, 2) + drift, V2(5, 1) + drift};  // reference frame = estimates at creation
    rs.sensor = V2(3, 3) + drift;
    map.insertRegionScan(rid, rs, part);

    const std::map<long, V2> lm{{100, truth[0]}, {101, truth[1]}, {102, truth[2]}};
    const auto vertices = trueRegionVertices(part, lm);
    ASSERT_EQ(vertices.size(), 3u);
    const LandmarkFramePoints pts = pointsAtTrueVertices(map, part, vertices);
    EXPECT_EQ(pts.regions_drawn, 1u);
    EXPECT_EQ(pts.regions_skipped, 0u);
    ASSERT_EQ(pts.points.size(), 2u);
    EXPECT_LT((pts.points[0] - V2(2, 2)).norm(), 1e-5);  // float storage in the points layer
    EXPECT_LT((pts.points[1] - V2(5, 1)).norm(), 1e-5);

    // Without the truth of one vertex and no edge to hang it from, the region is skipped.
    const LandmarkFramePoints none =
        pointsAtTrueVertices(map, part, {{100, truth[0]}, {101, truth[1]}});
    EXPECT_EQ(none.regions_skipped, 1u);
    EXPECT_EQ(none.points_skipped, 2u);
    EXPECT_TRUE(none.points.empty());
}

TEST(LaserCoverageTest, VirtualApexFollowsItsTrueEdge)
{
    // Vertex 102 is a virtual apex of edge (100, 101) at depth 4 (ltr::virtualApex); the
    // true edge is rotated and longer: the true apex is the apex of the true edge.
    const V2 a(0, 0), b(8, 0);
    const V2 apex = hymm::ltr::virtualApex(a, b, 1.0, 4.0);
    hymm::ltr::RegionPartition part{hymm::ltr::RegionPartition::Options()};
    long rid = -1;
    ASSERT_TRUE(part.tryAddRegion({100, 101, 102}, view({a, b, apex}), 0.0, &rid).accepted());
    const V2 ta(1, 1), tb(1, 10);
    const auto vertices = trueRegionVertices(part, {{100, ta}, {101, tb}});
    ASSERT_EQ(vertices.count(102), 1u);
    const V2 expected = hymm::ltr::virtualApex(ta, tb, 1.0, 4.0);
    EXPECT_LT((vertices.at(102) - expected).norm(), 1e-9);
}

}  // namespace
