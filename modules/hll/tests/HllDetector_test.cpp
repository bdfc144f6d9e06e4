// The HLL detector's steps on a synthetic occupancy grid with rectangular objects of
// known corners (thesis 6.1.3, Fig. 6.4): corners within a cell or two of the truth,
// nearest-neighbour pairs, rectangles 5 m around them, acceptance by the number of
// Gaussians inside (>= 200) and by overlap.
#include <gtest/gtest.h>
#include <hymm/hll/HllDetector.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace
{
using namespace hymm::hll;

/** How many candidates ended with `o`. */
size_t countOutcome(const std::vector<HllDetector::Candidate>& cands, HllDetector::Outcome o)
{
    return static_cast<size_t>(
        std::count_if(cands.begin(), cands.end(), [o](const HllDetector::Candidate& c) { return c.outcome == o; }));
}

/** A rectangle object: corners counter-clockwise. */
struct Box
{
    std::array<Vec2, 4> c;
    static Box make(const Vec2& origin, double l, double w, double yaw)
    {
        const double co = std::cos(yaw), s = std::sin(yaw);
        auto at = [&](double x, double y) { return Vec2(origin.x() + co * x - s * y, origin.y() + s * x + co * y); };
        return {{at(0, 0), at(l, 0), at(l, w), at(0, w)}};
    }
};

/** Free everywhere, interior of the objects unknown, outlines occupied: what an
 *  occupancy layer holds after the objects were seen from outside. */
mrpt::maps::COccupancyGridMap2D makeGrid(const std::vector<Box>& boxes, double res)
{
    mrpt::maps::COccupancyGridMap2D g(-10, 50, -10, 40, static_cast<float>(res));
    for (unsigned y = 0; y < g.getSizeY(); ++y)
        for (unsigned x = 0; x < g.getSizeX(); ++x) g.setCell(x, y, 0.1f);
    for (const auto& b : boxes)
        for (int e = 0; e < 4; ++e)
        {
            const Vec2 a = b.c[e], d = b.c[(e + 1) % 4];
            const int n = static_cast<int>(std::ceil((d - a).norm() / (0.25 * res)));
            for (int k = 0; k <= n; ++k)
            {
                const Vec2 p = a + (d - a) * (static_cast<double>(k) / n);
                g.setCell(static_cast<unsigned>(g.x2idx(p.x())), static_cast<unsigned>(g.y2idx(p.y())), 0.95f);
            }
        }
    return g;
}

/** Length of the segment a-d inside `r` (Liang-Barsky clipping in the rectangle's frame). */
double clippedLength(const OrientedRect& r, const Vec2& a, const Vec2& d)
{
    const Vec2 p = r.toLocal(a), q = r.toLocal(d), v = q - p;
    double t0 = 0, t1 = 1;
    for (int k = 0; k < 2; ++k)
        for (const double sgn : {-1.0, 1.0})
        {
            // sgn * (p + t v)_k <= half_k
            const double num = r.half[k] - sgn * p[k], den = sgn * v[k];
            if (std::abs(den) < 1e-15)
            {
                if (num < 0) return 0;
                continue;
            }
            const double t = num / den;
            if (den > 0) t1 = std::min(t1, t);
            else t0 = std::max(t0, t);
        }
    return t1 > t0 ? (t1 - t0) * v.norm() : 0.0;
}

double outlineLengthInside(const OrientedRect& r, const std::vector<Box>& boxes)
{
    double len = 0;
    for (const auto& b : boxes)
        for (int e = 0; e < 4; ++e) len += clippedLength(r, b.c[e], b.c[(e + 1) % 4]);
    return len;
}

/** SOG means every `spacing` along the outlines (a SOG layer of the same objects). */
std::vector<HllDetector::Gaussian> outlineGaussians(const std::vector<Box>& boxes, double spacing)
{
    std::vector<HllDetector::Gaussian> out;
    for (const auto& b : boxes)
        for (int e = 0; e < 4; ++e)
        {
            const Vec2 a = b.c[e], d = b.c[(e + 1) % 4];
            const int n = static_cast<int>(std::round((d - a).norm() / spacing));
            for (int k = 0; k < n; ++k)
                out.push_back({a + (d - a) * (static_cast<double>(k) / n), 0.01 * Mat2::Identity()});
        }
    return out;
}

// A: 6 x 3 m, C: 8 x 2.5 m rotated 30 deg: their short sides pair (3 m, 2.5 m apart);
// B: 2 x 1.5 m, too small to hold 200 Gaussians at 20 per metre (7 m of outline).
const Box kA = Box::make({0, 0}, 6, 3, 0);
const Box kB = Box::make({22, 0}, 2, 1.5, 0);
const Box kC = Box::make({20, 18}, 8, 2.5, M_PI / 6);

TEST(HllDetector, HarrisCornersAtTheTrueCorners)
{
    const double res = 0.2;
    const auto grid = makeGrid({kA, kB, kC}, res);
    HllDetector det(HllDetector::Options{});
    const auto corners = det.detectCorners(grid);
    size_t found = 0;
    for (const auto& b : {kA, kB, kC})
        for (const Vec2& t : b.c)
        {
            double best = 1e9;
            for (const Vec2& c : corners) best = std::min(best, (c - t).norm());
            EXPECT_LE(best, 2 * res * std::sqrt(2.0)) << "true corner " << t.transpose();
            found += best <= 2 * res * std::sqrt(2.0);
        }
    EXPECT_EQ(found, 12u);
    // No corner in the middle of a side or in free space: each is near a true corner.
    for (const Vec2& c : corners)
    {
        double best = 1e9;
        for (const auto& b : {kA, kB, kC})
            for (const Vec2& t : b.c) best = std::min(best, (c - t).norm());
        EXPECT_LE(best, 2 * res * std::sqrt(2.0)) << "spurious corner " << c.transpose();
    }
}

TEST(HllDetector, PairsAreNearestNeighboursWithinTheDistance)
{
    HllDetector::Options o;
    HllDetector det(o);
    // Two corners 3 m apart, a third 10 m from the second, a fourth 20 m from all.
    const std::vector<Vec2> c = {{0, 0}, {0, 3}, {10, 3}, {40, 40}};
    const auto pairs = det.pairCorners(c);
    // 0 <-> 1 mutual; 2's nearest is 1 (10 m <= 12 m); 3 has nobody within 12 m.
    ASSERT_EQ(pairs.size(), 2u);
    EXPECT_EQ(pairs[0], (std::pair<size_t, size_t>(0, 1)));
    EXPECT_EQ(pairs[1], (std::pair<size_t, size_t>(1, 2)));
    o.pair_max_distance_m = 9;
    EXPECT_EQ(HllDetector(o).pairCorners(c).size(), 1u);
}

TEST(HllDetector, RectangleIsTheMarginAroundThePair)
{
    HllDetector det(HllDetector::Options{});
    const Vec2 a(1, 2), b(1 + 3 * std::cos(0.4), 2 + 3 * std::sin(0.4));
    const OrientedRect r = det.pairRectangle(a, b);
    EXPECT_NEAR(r.phi, 0.4, 1e-12);
    EXPECT_NEAR((r.centre - 0.5 * (a + b)).norm(), 0, 1e-12);
    EXPECT_NEAR(r.half.x(), 1.5 + 5, 1e-12);
    EXPECT_NEAR(r.half.y(), 5, 1e-12);
    // 5 m beyond each corner along the pair, 5 m to each side, and no farther.
    const Vec2 u(std::cos(0.4), std::sin(0.4)), n(-u.y(), u.x());
    EXPECT_TRUE(r.contains(a - 4.99 * u));
    EXPECT_FALSE(r.contains(a - 5.01 * u));
    EXPECT_TRUE(r.contains(b + 4.99 * u + 4.99 * n));
    EXPECT_FALSE(r.contains(b + 5.01 * n));
    EXPECT_TRUE(r.toLocal(b).isApprox(Vec2(1.5, 0)));
}

TEST(HllDetector, OverlapBySeparatingAxes)
{
    OrientedRect a;
    a.half = Vec2(2, 1);
    OrientedRect b = a;
    b.centre = Vec2(4.5, 0);
    EXPECT_FALSE(overlaps(a, b));
    b.phi = M_PI / 2;  // now reaches x = 4.5 - 1 = 3.5 > 2: still apart
    EXPECT_FALSE(overlaps(a, b));
    b.centre = Vec2(2.9, 0);  // reaches 1.9 < 2
    EXPECT_TRUE(overlaps(a, b));
    // A diamond whose corner bounding boxes meet but whose areas do not.
    OrientedRect d;
    d.half = Vec2(1, 1);
    d.phi = M_PI / 4;
    d.centre = Vec2(2 + std::sqrt(2.0) + 0.05, 1 + std::sqrt(2.0) * 0.5);
    EXPECT_FALSE(overlaps(a, d));
}

TEST(HllDetector, AcceptsRectanglesWithEnoughGaussiansAndNoOverlap)
{
    const double res = 0.2;
    const std::vector<Box> boxes = {kA, kB, kC};
    const auto grid = makeGrid(boxes, res);
    const auto gaussians = outlineGaussians(boxes, 0.05);  // 20 per metre
    HllDetector det(HllDetector::Options{});
    const auto corners = det.detectCorners(grid);
    const auto cands = det.evaluate(corners, gaussians, {});
    // Six pairs: the two short sides of each object.
    ASSERT_EQ(cands.size(), 6u);
    size_t accepted = 0, few = 0, overlap = 0;
    for (const auto& c : cands)
    {
        switch (c.outcome)
        {
            case HllDetector::Outcome::accepted: ++accepted; break;
            case HllDetector::Outcome::too_few_gaussians: ++few; break;
            case HllDetector::Outcome::overlaps_candidate: ++overlap; break;
            default: ADD_FAILURE() << "unexpected outcome";
        }
        // The count against the analytic one: length of the true outlines inside the
        // rectangle (segments clipped exactly) times 20 Gaussians per metre.
        const double expected = 20.0 * outlineLengthInside(c.rect, boxes);
        EXPECT_NEAR(static_cast<double>(c.gaussians), expected, 4.0);
        EXPECT_EQ(c.outcome == HllDetector::Outcome::too_few_gaussians, expected < 200 - 4);
        // Each pair is a short side of one object: both corners on the same object.
        EXPECT_LT((c.b - c.a).norm(), 3.1);
    }
    // One per large object; the other rectangle of each overlaps it; B's two lack Gaussians.
    EXPECT_EQ(accepted, 2u);
    EXPECT_EQ(overlap, 2u);
    EXPECT_EQ(few, 2u);

    // An existing landmark over A: A's rectangles are now duplicates.
    OrientedRect existing;
    existing.centre = Vec2(3, 1.5);
    existing.half = Vec2(1, 1);
    const auto again = det.evaluate(corners, gaussians, {existing});
    EXPECT_EQ(countOutcome(again, HllDetector::Outcome::accepted), 1u);
    EXPECT_EQ(countOutcome(again, HllDetector::Outcome::overlaps_landmark), 2u);

    // The threshold is the rule: at 10 per metre nothing reaches 200.
    const auto sparse = det.evaluate(corners, outlineGaussians(boxes, 0.1), {});
    for (const auto& c : sparse) EXPECT_EQ(c.outcome, HllDetector::Outcome::too_few_gaussians);
}

/** Draws a pole of radius `r` at `c` occupied (a point landmark as the occupancy layer
 *  holds it: a blob of a few cells). */
void addPole(mrpt::maps::COccupancyGridMap2D& g, const Vec2& c, double r)
{
    for (unsigned y = 0; y < g.getSizeY(); ++y)
        for (unsigned x = 0; x < g.getSizeX(); ++x)
            if ((Vec2(g.idx2x(x), g.idx2y(y)) - c).norm() <= r) g.setCell(x, y, 0.95f);
}

double nearest(const Vec2& p, const std::vector<Vec2>& set)
{
    double best = 1e9;
    for (const Vec2& q : set) best = std::min(best, (p - q).norm());
    return best;
}

// Poles (thesis' point landmarks, radius 0.15-0.4 m) beside the objects: isolated ones,
// two 4.5 m apart (they would pair), one 1 m from a wall and one touching a wall.
const std::vector<Vec2> kPoles = {{10, 10}, {14, 12}, {35, 5}, {-5, 20}, {3, 4}, {3, -0.35}};

TEST(HllDetector, PolesGiveNoCornersAndObjectCornersRemain)
{
    const double res = 0.2;
    auto grid = makeGrid({kA, kB, kC}, res);
    for (const Vec2& p : kPoles) addPole(grid, p, 0.35);
    std::vector<Vec2> truth;
    for (const auto& b : {kA, kB, kC}) truth.insert(truth.end(), b.c.begin(), b.c.end());
    const double tol = 2 * res * std::sqrt(2.0);

    // Without the object filter (the rule before): the poles make corners of their own.
    HllDetector::Options raw;
    raw.min_object_extent_m = 0;
    size_t on_poles = 0;
    for (const Vec2& c : HllDetector(raw).detectCorners(grid)) on_poles += nearest(c, kPoles) < 1.0;
    EXPECT_GE(on_poles, 4u) << "the premise: a pole alone is a Harris corner";

    // With it and the point landmarks known: only the twelve object corners.
    HllDetector det(HllDetector::Options{});
    HllDetector::CornerStats st;
    const auto corners = det.detectCorners(grid, kPoles, &st);
    EXPECT_GE(st.components_dropped, 5u);  // the five poles apart from the walls
    for (const Vec2& c : corners)
    {
        EXPECT_LE(nearest(c, truth), tol) << "corner off the objects " << c.transpose();
        EXPECT_GE(nearest(c, kPoles), det.options().landmark_clearance_m);
    }
    size_t found = 0;
    for (const Vec2& t : truth) found += nearest(t, corners) <= tol;
    EXPECT_EQ(found, 12u);

    // Even without the landmark list, no isolated pole makes a corner.
    for (const Vec2& c : det.detectCorners(grid))
        for (size_t k = 0; k < 4; ++k) EXPECT_GT((c - kPoles[k]).norm(), 1.0) << "pole " << k;

    // And the HLLs are those of the objects alone: six pairs, two accepted, no pole inside
    // an accepted rectangle's pair.
    const auto cands = det.evaluate(corners, outlineGaussians({kA, kB, kC}, 0.05), {});
    EXPECT_EQ(cands.size(), 6u);
    size_t accepted = 0;
    for (const auto& c : cands)
    {
        accepted += c.outcome == HllDetector::Outcome::accepted;
        EXPECT_LE(nearest(c.a, truth), tol);
        EXPECT_LE(nearest(c.b, truth), tol);
    }
    EXPECT_EQ(accepted, 2u);
}

TEST(HllDetector, OutlineLengthDoesNotDependOnTheGaussianDensity)
{
    const double res = 0.2;
    const std::vector<Box> boxes = {kA, kB, kC};
    HllDetector::Options o;
    o.min_gaussians = 3;
    o.min_outline_m = 12;
    HllDetector det(o);
    const auto corners = det.detectCorners(makeGrid(boxes, res));
    // The same outlines at 5, 10 and 20 Gaussians per metre (a wall seen once, twice,
    // four times by the SOG layer): the count grows with the density, the length not.
    std::vector<std::vector<HllDetector::Candidate>> runs;
    for (const double spacing : {0.2, 0.1, 0.05}) runs.push_back(det.evaluate(corners, outlineGaussians(boxes, spacing), {}));
    ASSERT_EQ(runs[0].size(), 6u);
    for (size_t k = 0; k < runs[0].size(); ++k)
    {
        // Candidates are sorted by count: find the same pair in each run.
        for (const auto& run : runs)
        {
            const auto same = std::find_if(run.begin(), run.end(), [&](const HllDetector::Candidate& c)
                                           { return c.a == runs[0][k].a && c.b == runs[0][k].b; });
            ASSERT_NE(same, run.end());
            // Against the true outline clipped to the rectangle: the box walls run along
            // the rectangle's axes (within one cell per wall end).
            const double truth = outlineLengthInside(same->rect, boxes);
            EXPECT_NEAR(same->outline_m, truth, 8 * o.outline_cell_m) << "pair " << k;
            EXPECT_EQ(same->outcome == HllDetector::Outcome::outline_too_short,
                      same->outline_m < o.min_outline_m);
            EXPECT_NE(same->outcome, HllDetector::Outcome::too_few_gaussians);
        }
    }
    // A's and C's rectangles hold more than 12 m, B's (7 m of outline) less.
    for (const auto& run : runs)
    {
        EXPECT_EQ(countOutcome(run, HllDetector::Outcome::accepted), 2u);
        EXPECT_EQ(countOutcome(run, HllDetector::Outcome::outline_too_short), 2u);
    }
}

TEST(HllDetector, EmptyOrTinyGridsGiveNoCorners)
{
    HllDetector det(HllDetector::Options{});
    mrpt::maps::COccupancyGridMap2D empty(0, 10, 0, 10, 0.2f);
    EXPECT_TRUE(det.detectCorners(empty).empty());
    mrpt::maps::COccupancyGridMap2D tiny(0, 0.4f, 0, 0.4f, 0.2f);
    EXPECT_TRUE(det.detectCorners(tiny).empty());
    EXPECT_TRUE(det.evaluate({}, {}, {}).empty());
    HllDetector::Options bad;
    bad.cell_size_m = 0;
    EXPECT_THROW(HllDetector{bad}, std::invalid_argument);
}

}  // namespace
