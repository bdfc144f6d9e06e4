// MotionDetector (thesis Sec. 6.3): differencing, low-pass, fast motion limited to the
// regions in view, amortised slow motion, layers that move with the landmarks. Scenes
// are simulated analytically on the lattice partition of the dense tests.
#include "../../dense/tests/synthetic_partition.h"

#include <gtest/gtest.h>
#include <hymm/dense/HybridMetricMap.h>
#include <hymm/dynamic/MotionDetector.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/random/RandomGenerators.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <random>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

namespace
{
using namespace hymm::dense::synthetic;
using hymm::dense::HybridMetricMap;
using hymm::dynamic::MotionDetector;
using hymm::dynamic::MotionKind;

struct Box
{
    Eigen::Vector2d lo, hi;
    bool contains(const Eigen::Vector2d& p, double margin = 0) const
    {
        return p.x() >= lo.x() - margin && p.x() <= hi.x() + margin && p.y() >= lo.y() - margin &&
               p.y() <= hi.y() + margin;
    }
};

/** Ray / axis-aligned box (slab test); entry distance or nullopt. */
std::optional<double> rayBox(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Box& b)
{
    double t0 = 0, t1 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 2; ++k)
    {
        if (std::abs(d[k]) < 1e-12)
        {
            if (o[k] < b.lo[k] || o[k] > b.hi[k]) return std::nullopt;
            continue;
        }
        double a = (b.lo[k] - o[k]) / d[k], c = (b.hi[k] - o[k]) / d[k];
        if (a > c) std::swap(a, c);
        t0 = std::max(t0, a);
        t1 = std::min(t1, c);
    }
    if (t0 > t1) return std::nullopt;
    return t0;
}

/** Sensor at (1, 7.5) looking +x over the 5 x 4 lattice ([0, 20] x [0, 15]); a wall
 *  x in [17, 17.4] and the given boxes; ranges with noise `std_range`. */
hymm::dense::ScanPoints scanOf(const std::vector<Box>& boxes, double std_range,
                               mrpt::random::CRandomGenerator& rng)
{
    hymm::dense::ScanPoints s;
    const Eigen::Vector2d o(1.0, 7.5);
    std::vector<Box> all = boxes;
    all.push_back({{17.0, 0.0}, {17.4, 15.0}});
    for (int k = 0; k <= 320; ++k)
    {
        const double th = (-80.0 + 0.5 * k) * M_PI / 180.0;
        const Eigen::Vector2d d(std::cos(th), std::sin(th));
        double r = std::numeric_limits<double>::infinity();
        for (const auto& b : all)
            if (const auto t = rayBox(o, d, b)) r = std::min(r, *t);
        if (!std::isfinite(r) || r > 24) continue;
        r += rng.drawGaussian1D(0.0, std_range);
        s.points.emplace_back(r * std::cos(th), r * std::sin(th));
    }
    return s;
}

const mrpt::math::TPose2D kSensorPose{1.0, 7.5, 0.0};

HybridMetricMap::Options mapOptions()
{
    HybridMetricMap::Options o;
    o.enable_points = false;
    o.occupancy.cell_size_m = 0.2;
    return o;
}

std::vector<long> inView(const hymm::ltr::RegionPartition& p)
{
    return p.regionsInBox(Eigen::Vector2d(1.0 - 24, 7.5 - 24), Eigen::Vector2d(1.0 + 24, 7.5 + 24));
}

hymm::dynamic::OccupancySnapshot blank(int n, float p)
{
    hymm::dynamic::OccupancySnapshot s;
    s.nx = s.ny = n;
    s.cell_size = 0.1;
    s.p.assign(static_cast<size_t>(n * n), p);
    s.inside.assign(static_cast<size_t>(n * n), 1);
    return s;
}

TEST(MotionDifference, LowPassRemovesThinLinesKeepsBlobsIgnoresNewlySeen)
{
    const int n = 40;
    auto then = blank(n, 0.03f), now = blank(n, 0.03f);
    auto at = [&](auto& s, int x, int y) -> float& { return s.p[static_cast<size_t>(y * n + x)]; };
    for (int y = 5; y < 35; ++y) at(now, 5, y) = 0.97f;  // a one-cell line appears
    for (int y = 15; y < 23; ++y)
        for (int x = 20; x < 28; ++x) at(then, x, y) = 0.97f;  // an 8 x 8 object leaves
    for (int y = 30; y < 38; ++y)
        for (int x = 20; x < 38; ++x) at(then, x, y) = 0.5f;  // unknown, now seen free
    const auto raw = hymm::dynamic::differenceOccupancy(then, now, 0.0, 0.5);
    const auto lp = hymm::dynamic::differenceOccupancy(then, now, 2.0, 0.5);
    auto m = [&](const hymm::dynamic::Difference& d, int x, int y) {
        return d.mask[static_cast<size_t>(y * n + x)] != 0;
    };
    EXPECT_TRUE(m(raw, 5, 20));
    EXPECT_FALSE(m(lp, 5, 20));  // the thin line is filtered out
    EXPECT_TRUE(m(raw, 24, 19));
    EXPECT_TRUE(m(lp, 24, 19));  // the object's interior survives the filter
    EXPECT_FALSE(m(raw, 30, 33));  // 0.5 -> 0.03 is not above 0.5
    EXPECT_FALSE(m(lp, 30, 33));
    EXPECT_NEAR(raw.raw[static_cast<size_t>(19 * n + 24)], 0.94f, 1e-6);
    EXPECT_EQ(raw.marked(), 30u + 64u);
    EXPECT_LT(lp.marked(), 64u);
    EXPECT_GT(lp.marked(), 20u);
    auto other = blank(n + 1, 0.03f);
    EXPECT_THROW(hymm::dynamic::differenceOccupancy(then, other, 0.0, 0.5), std::invalid_argument);
}

// A static outline whose cells flip alone (pose and laser noise at 0.2 m cells) against a
// moved object's outline: the cluster filter drops the isolated cells and keeps the
// object's, whatever the shape of its cluster (a line, an L, a diagonal run of cells).
TEST(MotionDifference, SmallClustersAreDroppedLargerOnesKeptWhole)
{
    const int n = 30;
    auto then = blank(n, 0.03f), now = blank(n, 0.03f);
    auto at = [&](auto& s, int x, int y) -> float& { return s.p[static_cast<size_t>(y * n + x)]; };
    at(now, 2, 2) = 0.97f;                                   // one cell
    at(now, 10, 2) = at(now, 11, 3) = 0.97f;                 // two cells, touching corners
    for (int k = 0; k < 3; ++k) at(now, 20 + k, 20 + k) = 0.97f;  // a diagonal run of 3
    for (int y = 10; y < 16; ++y) at(then, 5, y) = 0.97f;    // an L of 10 cells leaves
    for (int x = 6; x < 10; ++x) at(then, x, 15) = 0.97f;
    auto m = [&](const hymm::dynamic::Difference& d, int x, int y) {
        return d.mask[static_cast<size_t>(y * n + x)] != 0;
    };
    const auto all = hymm::dynamic::differenceOccupancy(then, now, 0.0, 0.5);
    EXPECT_EQ(all.marked(), 1u + 2u + 3u + 10u);
    const auto c2 = hymm::dynamic::differenceOccupancy(then, now, 0.0, 0.5, 2);
    EXPECT_FALSE(m(c2, 2, 2));
    EXPECT_TRUE(m(c2, 10, 2) && m(c2, 11, 3));  // 8-connected: one cluster of 2
    EXPECT_EQ(c2.marked(), 2u + 3u + 10u);
    const auto c3 = hymm::dynamic::differenceOccupancy(then, now, 0.0, 0.5, 3);
    EXPECT_EQ(c3.marked(), 3u + 10u);
    EXPECT_TRUE(m(c3, 21, 21) && m(c3, 5, 10) && m(c3, 9, 15));
    const auto c11 = hymm::dynamic::differenceOccupancy(then, now, 0.0, 0.5, 11);
    EXPECT_EQ(c11.marked(), 0u);
    // Only the mask changes; the difference images are those of the unfiltered call.
    EXPECT_EQ(c3.raw, all.raw);
    EXPECT_EQ(c3.filtered, all.filtered);
    // The filter applied to a mask twice gives the same mask (it leaves only 0 and 1).
    auto again = c3;
    hymm::dynamic::removeSmallClusters(again, 3);
    EXPECT_EQ(again.mask, c3.mask);
}

// A wall whose edge moved by one cell between the snapshots (its returns now land a cell
// further out), a box that left and a box that arrived: with a tolerance of one cell the
// wall's change is no motion, both boxes are, whole. A wall that moved by two cells is
// motion for a one-cell tolerance and not for a two-cell one.
TEST(MotionDifference, EdgesThatMovedWithinTheToleranceAreNotMotion)
{
    const int n = 40;
    auto then = blank(n, 0.03f), now = blank(n, 0.03f);
    auto at = [&](auto& s, int x, int y) -> float& { return s.p[static_cast<size_t>(y * n + x)]; };
    for (int y = 2; y < 30; ++y)
    {
        at(then, 3, y) = 0.95f;  // wall A: x = 3 -> 4
        at(now, 4, y) = 0.95f;
        at(then, 30, y) = 0.95f;  // wall B: x = 30 -> 32
        at(now, 32, y) = 0.95f;
    }
    for (int y = 5; y < 9; ++y)
        for (int x = 10; x < 14; ++x)
        {
            at(then, x, y) = 0.9f;       // box that left
            at(now, x, y + 15) = 0.9f;   // box that arrived
        }
    const auto m = [&](const hymm::dynamic::Difference& d, int x, int y) {
        return d.mask[static_cast<size_t>(y * n + x)] != 0;
    };
    const auto off = hymm::dynamic::differenceOccupancy(then, now, 0.0, 0.5, 1, 0);
    EXPECT_EQ(off.marked(), 4u * 28u + 2u * 16u);  // both walls' old and new cells, both boxes
    const auto t1 = hymm::dynamic::differenceOccupancy(then, now, 0.0, 0.5, 1, 1);
    for (int y = 2; y < 30; ++y)
    {
        EXPECT_FALSE(m(t1, 3, y) || m(t1, 4, y)) << y;  // wall A moved one cell
        EXPECT_TRUE(m(t1, 30, y) && m(t1, 32, y)) << y;  // wall B two
    }
    for (int y = 5; y < 9; ++y)
        for (int x = 10; x < 14; ++x) EXPECT_TRUE(m(t1, x, y) && m(t1, x, y + 15)) << x << ' ' << y;
    EXPECT_EQ(t1.marked(), 2u * 28u + 2u * 16u);
    const auto t2 = hymm::dynamic::differenceOccupancy(then, now, 0.0, 0.5, 1, 2);
    EXPECT_EQ(t2.marked(), 2u * 16u);
    // The tolerance acts on the difference, so the low-pass sees no trace of wall A.
    const auto t1f = hymm::dynamic::differenceOccupancy(then, now, 1.0, 0.5, 1, 1);
    for (int y = 2; y < 30; ++y) EXPECT_EQ(t1f.filtered[static_cast<size_t>(y * n + 3)], 0.0f) << y;
    // Cells outside the region are neither evidence of an edge nor of motion.
    auto then_out = then;
    for (int y = 2; y < 30; ++y) then_out.inside[static_cast<size_t>(y * n + 3)] = 0;
    EXPECT_GT(hymm::dynamic::differenceOccupancy(then_out, now, 0.0, 0.5, 1, 1).marked(), t1.marked());
}

/** A box 1 x 1 m moving north along x in [9, 10] at 1.3 m/s in front of a wall. */
struct FastScene
{
    WallWorld w;
    HybridMetricMap map{mapOptions()};
    mrpt::random::CRandomGenerator rng{7};
    Box moverAt(double t) const
    {
        const double y = 1.0 + 1.3 * t;
        return {{9.0, y}, {10.0, y + 1.0}};
    }
    /** Runs 10 s of scans at 10 Hz, stepping `det`. */
    void run(MotionDetector& det, std::vector<MotionDetector::StepReport>* reps = nullptr)
    {
        for (int k = 0; k <= 100; ++k)
        {
            const double t = 0.1 * k;
            map.insertScan(scanOf({moverAt(t)}, 0.1, rng), kSensorPose, w.partition);
            const auto r = det.step(map, inView(w.partition), t);
            if (reps) reps->push_back(r);
        }
    }
};

/** Marked cells of the rendered fast layer: on the mover's swept band vs elsewhere. */
struct Score
{
    size_t on_swept = 0, off_swept = 0, near_wall = 0;
};
Score scoreFast(const MotionDetector& det, const hymm::ltr::RegionPartition& p)
{
    mrpt::maps::COccupancyGridMap2D g(0.0f, 20.0f, 0.0f, 15.0f, 0.1f);
    det.renderInto(MotionKind::Fast, p, g);
    Score s;
    const Box swept{{9.0, 1.0}, {10.0, 15.0}};
    for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
        for (unsigned cx = 0; cx < g.getSizeX(); ++cx)
        {
            if (g.getCell(cx, cy) < 0.9f) continue;
            const Eigen::Vector2d c(g.idx2x(cx), g.idx2y(cy));
            if (swept.contains(c, 0.3))
                ++s.on_swept;
            else
                ++s.off_swept;
            if (std::abs(c.x() - 17.0) < 0.5) ++s.near_wall;
        }
    return s;
}

TEST(MotionDetector, FastMotionMarksTheSweptBandOnlyInView)
{
    FastScene sc;
    MotionDetector::Options o;
    o.enable_slow = false;
    MotionDetector det(o);
    std::vector<MotionDetector::StepReport> reps;
    sc.run(det, &reps);
    // Every region is differenced at most once per second: never in the first second,
    // all that were seen at t = 0 at t = 1 s, and at most 10 times in 10 s.
    size_t differenced = 0;
    for (size_t k = 1; k < 10; ++k) EXPECT_EQ(reps[k].fast_differenced, 0u) << k;
    EXPECT_GT(reps[10].fast_differenced, 0u);
    for (const auto& r : reps) differenced += r.fast_differenced;
    EXPECT_LE(differenced, 10 * sc.w.partition.size());
    EXPECT_GT(differenced, 0u);
    EXPECT_EQ(reps.back().slow_differenced, 0u);
    const auto s = scoreFast(det, sc.w.partition);
    EXPECT_GT(s.on_swept, 40u);  // the near face of the box, about 13 m of it
    EXPECT_LT(static_cast<double>(s.off_swept), 0.25 * static_cast<double>(s.on_swept));
    EXPECT_EQ(det.markedCells(MotionKind::Slow), 0u);
}

TEST(MotionDetector, WithoutLowPassTheStaticContourFlickers)
{
    FastScene a, b;
    MotionDetector::Options o;
    o.enable_slow = false;
    MotionDetector with(o);
    o.lowpass = false;
    MotionDetector without(o);
    a.run(with);
    b.run(without);
    const auto sw = scoreFast(with, a.w.partition), so = scoreFast(without, b.w.partition);
    // Range noise moves the wall's returns between cells; the low-pass removes most of
    // that flicker (Fig. 6.9 c-d).
    EXPECT_GT(so.near_wall, 3 * sw.near_wall);
    EXPECT_GT(so.off_swept, 3 * sw.off_swept);
}

TEST(MotionDetector, OnlyRegionsInViewAreDifferencedForFastMotion)
{
    FastScene sc;
    MotionDetector::Options o;
    o.enable_slow = false;
    MotionDetector det(o);
    // Only the regions whose box holds the sensor: a strict subset of those scanned.
    const auto near = sc.w.partition.regionsInBox(Eigen::Vector2d(0.5, 7.0), Eigen::Vector2d(1.5, 8.0));
    ASSERT_LT(near.size(), inView(sc.w.partition).size());
    size_t total = 0;
    for (int k = 0; k <= 20; ++k)
    {
        sc.map.insertScan(scanOf({sc.moverAt(0.1 * k)}, 0.05, sc.rng), kSensorPose, sc.w.partition);
        total += det.step(sc.map, near, 0.1 * k).fast_differenced;
    }
    // Each near region twice (t = 1 s and 2 s) at most; some get their first
    // occupancy only after the first scans.
    EXPECT_GT(total, 0u);
    EXPECT_LE(total, 2 * near.size());
    for (long id : sc.w.partition.regionIds())
        if (std::find(near.begin(), near.end(), id) == near.end())
        {
            const auto* l = det.layer(MotionKind::Fast, id);
            EXPECT_TRUE(!l || !l->initialised()) << id;
        }
}

TEST(MotionDetector, SlowMotionFindsARemovedObjectAmortised)
{
    WallWorld w;
    HybridMetricMap map(mapOptions());
    mrpt::random::CRandomGenerator rng(3);
    const Box container{{8.0, 6.0}, {11.0, 9.0}};
    MotionDetector::Options o;
    o.enable_fast = false;
    o.slow_period_s = 20.0;
    o.slow_max_regions_per_call = 1;
    MotionDetector det(o);
    const auto view = inView(w.partition);
    size_t max_per_call = 0, differenced = 0;
    double t = 0;
    auto pass = [&](const std::vector<Box>& boxes, int scans) {
        for (int k = 0; k < scans; ++k, t += 0.1)
        {
            map.insertScan(scanOf(boxes, 0.05, rng), kSensorPose, w.partition);
            const auto r = det.step(map, view, t);
            max_per_call = std::max(max_per_call, r.slow_differenced);
            differenced += r.slow_differenced;
        }
    };
    auto away = [&](double until) {
        for (; t < until; t += 0.1)
        {
            const auto r = det.step(map, {}, t);
            max_per_call = std::max(max_per_call, r.slow_differenced);
            differenced += r.slow_differenced;
        }
    };
    pass({container}, 30);  // first pass: the container is there
    away(15.0);             // the vehicle is elsewhere; first references taken on leaving
    EXPECT_EQ(det.markedCells(MotionKind::Slow), 0u);
    pass({}, 30);  // second pass: it is gone
    away(60.0);
    EXPECT_EQ(max_per_call, 1u);  // amortised: one region per call
    EXPECT_GE(differenced, view.size());  // yet every region was differenced
    // The container's near face (x = 8) is marked; the wall and the free space are not.
    size_t on_face = 0, elsewhere = 0;
    mrpt::maps::COccupancyGridMap2D g(0.0f, 20.0f, 0.0f, 15.0f, 0.1f);
    det.renderInto(MotionKind::Slow, w.partition, g);
    for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
        for (unsigned cx = 0; cx < g.getSizeX(); ++cx)
        {
            if (g.getCell(cx, cy) < 0.9f) continue;
            const Eigen::Vector2d c(g.idx2x(cx), g.idx2y(cy));
            ++(container.contains(c, 0.4) ? on_face : elsewhere);
        }
    EXPECT_GT(on_face, 10u);
    EXPECT_EQ(elsewhere, 0u);
    EXPECT_TRUE(det.isDynamic(MotionKind::Slow, w.partition, Eigen::Vector2d(8.0, 7.5)) ||
                det.isDynamic(MotionKind::Slow, w.partition, Eigen::Vector2d(8.05, 7.55)) ||
                det.isDynamic(MotionKind::Slow, w.partition, Eigen::Vector2d(7.95, 7.45)));
    EXPECT_FALSE(det.isDynamic(w.partition, Eigen::Vector2d(17.0, 7.5)));

    // Static occupancy without the dynamic cells: the marked cells read the prior.
    mrpt::maps::COccupancyGridMap2D full, stat;
    map.renderOccupancy(w.partition, 0.1, full);
    det.renderStaticOccupancy(map, w.partition, 0.1, stat);
    size_t changed = 0;
    for (unsigned cy = 0; cy < stat.getSizeY(); ++cy)
        for (unsigned cx = 0; cx < stat.getSizeX(); ++cx)
            if (std::abs(stat.getCell(cx, cy) - full.getCell(cx, cy)) > 1e-3)
            {
                EXPECT_NEAR(stat.getCell(cx, cy), 0.5f, 0.01f);
                ++changed;
            }
    EXPECT_GT(changed, 0u);
}

/** Slow cells marked after a 3 x 3 m container leaves (the scene of the test above), or
 *  is replaced by the boxes `after`. */
size_t slowCellsAfterARemoval(MotionDetector::Options o, const std::vector<Box>& after = {})
{
    WallWorld w;
    HybridMetricMap map(mapOptions());
    mrpt::random::CRandomGenerator rng(3);
    o.slow_period_s = 20.0;
    MotionDetector det(o);
    const auto view = inView(w.partition);
    double t = 0;
    for (const std::vector<Box>& boxes : {std::vector<Box>{{{8.0, 6.0}, {11.0, 9.0}}}, after})
    {
        for (int k = 0; k < 30; ++k, t += 0.1)
        {
            map.insertScan(scanOf(boxes, 0.05, rng), kSensorPose, w.partition);
            det.step(map, view, t);
        }
        for (const double until = t + 30.0; t < until; t += 0.1) det.step(map, {}, t);
    }
    return det.markedCells(MotionKind::Slow);
}

// Each layer's cluster minimum and edge tolerance reach that layer alone: set huge on one
// layer, they take marks from it (the cluster minimum all of them; the tolerance those
// with an occupied cell of the same region in the other snapshot) and leave the other
// layer unchanged.
TEST(MotionDetector, ClusterMinimumsAndEdgeTolerancesActOnTheirOwnLayer)
{
    const auto fastCells = [](const MotionDetector::Options& o) {
        FastScene sc;
        MotionDetector det(o);
        sc.run(det);
        return det.markedCells(MotionKind::Fast);
    };
    MotionDetector::Options fast_only;
    fast_only.enable_slow = false;
    const size_t fast = fastCells(fast_only);
    EXPECT_GT(fast, 0u);
    MotionDetector::Options slow_only;
    slow_only.enable_fast = false;
    using Setter = void (*)(MotionDetector::Options&);
    struct Knob
    {
        Setter on_fast, on_slow;
        std::vector<Box> after;  // the slow scene: the container leaves, or moves 0.6 m
    };
    const Knob knobs[] = {
        {[](MotionDetector::Options& o) { o.fast_min_cluster_cells = 1000000; },
         [](MotionDetector::Options& o) { o.slow_min_cluster_cells = 1000000; }, {}},
        {[](MotionDetector::Options& o) { o.fast_shift_tolerance_cells = 100; },
         [](MotionDetector::Options& o) { o.slow_shift_tolerance_cells = 100; }, {{{8.6, 6.0}, {11.6, 9.0}}}},
    };
    for (const Knob& k : knobs)
    {
        auto o = fast_only;
        k.on_slow(o);
        EXPECT_EQ(fastCells(o), fast);
        o = fast_only;
        k.on_fast(o);
        EXPECT_LT(fastCells(o), fast);
        const size_t slow = slowCellsAfterARemoval(slow_only, k.after);
        EXPECT_GT(slow, 0u);
        o = slow_only;
        o.enable_fast = true;
        k.on_fast(o);
        EXPECT_EQ(slowCellsAfterARemoval(o, k.after), slow);
        o = slow_only;
        k.on_slow(o);
        EXPECT_LT(slowCellsAfterARemoval(o, k.after), slow);
    }
}

TEST(MotionDetector, LayersMoveWithTheLandmarks)
{
    FastScene sc;
    MotionDetector::Options o;
    o.enable_slow = false;
    MotionDetector det(o);
    sc.run(det);
    // A marked point before the correction.
    std::optional<Eigen::Vector2d> marked;
    for (double y = 2.0; y < 14 && !marked; y += 0.05)
        for (double x = 8.5; x < 10.5 && !marked; x += 0.05)
            if (det.isDynamic(MotionKind::Fast, sc.w.partition, Eigen::Vector2d(x, y)))
                marked = Eigen::Vector2d(x, y);
    ASSERT_TRUE(marked.has_value());
    // Every landmark shifted by (3, -2) (a rigid correction): the mark follows.
    std::map<long, Eigen::Vector2d> moved = sc.w.lattice.landmarks();
    for (auto& [id, p] : moved) p += Eigen::Vector2d(3.0, -2.0);
    const auto view = makeDenseView(moved, Eigen::Vector3d::Zero());
    sc.w.partition.updateVertexPositions(view);
    EXPECT_TRUE(det.isDynamic(MotionKind::Fast, sc.w.partition, *marked + Eigen::Vector2d(3.0, -2.0)));
    mrpt::maps::COccupancyGridMap2D g(0.0f, 25.0f, -3.0f, 15.0f, 0.1f);
    det.renderInto(MotionKind::Fast, sc.w.partition, g);
    EXPECT_GT(g.getPos(static_cast<float>(marked->x() + 3.0), static_cast<float>(marked->y() - 2.0)), 0.9f);
}

TEST(MotionDetector, RegionsRemovedByIdLeaveTheDetectorAsTheWalkDoes)
{
    // Two detectors on one map: one told the removed ids, one walking the map.
    FastScene sc;
    MotionDetector by_ids(MotionDetector::Options{}), by_walk(MotionDetector::Options{});
    auto stepBoth = [&](int k0, int k1) {
        for (int k = k0; k <= k1; ++k)
        {
            const double t = 0.1 * k;
            sc.map.insertScan(scanOf({sc.moverAt(t)}, 0.1, sc.rng), kSensorPose, sc.w.partition);
            by_ids.step(sc.map, inView(sc.w.partition), t);
            by_walk.step(sc.map, inView(sc.w.partition), t);
        }
    };
    stepBoth(0, 50);
    ASSERT_GT(by_ids.size(), 1u);
    const long victim = sc.w.partition.regionIds().front();
    sc.w.partition.removeRegion(victim);
    const auto removed = sc.map.removeRegions({victim});
    by_ids.removeRegions(removed);
    by_ids.removeRegions({123456});  // unknown id: nothing happens
    by_walk.removeStaleRegions(sc.map);
    EXPECT_EQ(by_ids.layer(MotionKind::Fast, victim), nullptr);
    EXPECT_EQ(by_ids.size(), by_walk.size());
    stepBoth(51, 100);
    for (auto kind : {MotionKind::Fast, MotionKind::Slow})
    {
        EXPECT_EQ(by_ids.markedCells(kind), by_walk.markedCells(kind));
        for (long id : sc.w.partition.regionIds())
        {
            const auto *a = by_ids.layer(kind, id), *b = by_walk.layer(kind, id);
            ASSERT_EQ(a == nullptr, b == nullptr);
            if (!a) continue;
            ASSERT_EQ(a->sizeX() * a->sizeY(), b->sizeX() * b->sizeY());
            for (int iy = 0; iy < a->sizeY(); ++iy)
                for (int ix = 0; ix < a->sizeX(); ++ix) EXPECT_EQ(a->cell(ix, iy), b->cell(ix, iy));
        }
    }
    // Its queued slow entry is skipped when due.
    EXPECT_NO_THROW(by_ids.step(sc.map, {}, 1000.0));
}

/** The slow scene of SlowMotionFindsARemovedObjectAmortised with the container beyond
 *  every region (above the lattice, y > 15, before a wall), where only the fallback keeps
 *  its returns. */
struct TileScene
{
    explicit TileScene(hymm::dense::FallbackFrame frame = hymm::dense::FallbackFrame::Affine)
        : map([frame] {
              auto o = mapOptions();
              o.fallback_max_distance_m = 10.0;
              o.fallback_tile_m = 10.0;
              o.fallback_frame = frame;
              return o;
          }())
    {
    }
    WallWorld w;
    HybridMetricMap map;
    mrpt::random::CRandomGenerator rng{5};
    const Box container{{6.0, 17.0}, {9.0, 19.0}};
    const Box back_wall{{2.0, 22.0}, {16.0, 22.4}};  // what the beams meet once it is gone
    /** Inside the lattice, under the tiles that reach into it (y in [10, 20]); removed
     *  with the container when `inner`. */
    const Box inner_box{{8.0, 11.0}, {10.0, 13.0}};
    /** [m] how far the back wall stands farther away in the second pass (a static wall seen
     *  through another estimate of the anchor). */
    double wall_shift = 0;
    double t = 0;
    /** A pass of 30 scans with or without the container, then 30 s away. `tiles`: the
     *  detector is given the fallback tiles in view; `regions`: the regions in view. */
    void run(MotionDetector& det, bool tiles, bool regions = true, bool inner = false)
    {
        const Eigen::Vector2d lo(1.0 - 24, 7.5 - 24), hi(1.0 + 24, 7.5 + 24);
        for (const bool present : {true, false})
        {
            for (int k = 0; k < 30; ++k, t += 0.1)
            {
                const Eigen::Vector2d shift(0.0, present ? 0.0 : wall_shift);
                std::vector<Box> boxes{{back_wall.lo + shift, back_wall.hi + shift}};
                if (present) boxes.push_back(container);
                if (present && inner) boxes.push_back(inner_box);
                map.insertScan(scanOf(boxes, 0.05, rng), kSensorPose, w.partition);
                const auto view = regions ? inView(w.partition) : std::vector<long>{};
                if (tiles)
                    det.step(map, view, map.fallbackTilesInBox(w.partition, lo, hi), t);
                else
                    det.step(map, view, t);
            }
            for (const double until = t + 30.0; t < until; t += 0.1) det.step(map, {}, {}, t);
        }
    }
    /** Marked cells of the rendered slow layer near the container / elsewhere. */
    std::pair<size_t, size_t> marks(const MotionDetector& det) const
    {
        mrpt::maps::COccupancyGridMap2D g(-5.0f, 25.0f, -5.0f, 30.0f, 0.1f);
        det.renderInto(MotionKind::Slow, w.partition, g);
        size_t on = 0, off = 0;
        for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
            for (unsigned cx = 0; cx < g.getSizeX(); ++cx)
                if (g.getCell(cx, cy) > 0.9f)
                    ++(container.contains(Eigen::Vector2d(g.idx2x(cx), g.idx2y(cy)), 0.4) ? on : off);
        return {on, off};
    }
    /** A point of the container's near faces that isDynamic() reports, if any. */
    std::optional<Eigen::Vector2d> markedPoint(const MotionDetector& det) const
    {
        for (double y = 16.6; y < 19.4; y += 0.05)
            for (double x = 5.6; x < 9.4; x += 0.05)
                if (det.isDynamic(MotionKind::Slow, w.partition, Eigen::Vector2d(x, y))) return Eigen::Vector2d(x, y);
        return std::nullopt;
    }
};

TEST(MotionDetector, ObjectsBeyondEveryRegionAreFoundInTheFallbackTiles)
{
    MotionDetector::Options o;
    o.enable_fast = false;
    o.slow_period_s = 20.0;
    TileScene with_tiles, regions_only;
    MotionDetector det(o), det_regions(o);
    with_tiles.run(det, true);
    regions_only.run(det_regions, false);
    ASSERT_GT(with_tiles.map.fallbackTiles(), 0u);
    EXPECT_GT(det.tiles(), 0u);
    EXPECT_EQ(det_regions.tiles(), 0u);
    // No region holds the container: without the tiles nothing marks it.
    EXPECT_EQ(regions_only.marks(det_regions).first, 0u);
    EXPECT_FALSE(regions_only.markedPoint(det_regions).has_value());
    const auto [on, off] = with_tiles.marks(det);
    EXPECT_GT(on, 10u);
    EXPECT_EQ(off, 0u);
    const auto marked = with_tiles.markedPoint(det);
    ASSERT_TRUE(marked.has_value());
    EXPECT_TRUE(det.isDynamic(with_tiles.w.partition, *marked));
    EXPECT_FALSE(det.isDynamic(with_tiles.w.partition, Eigen::Vector2d(17.0, 7.5)));  // the wall

    // The marks live in the anchors' frames: a rigid correction of the landmarks moves them.
    std::map<long, Eigen::Vector2d> moved = with_tiles.w.lattice.landmarks();
    for (auto& [id, p] : moved) p += Eigen::Vector2d(3.0, -2.0);
    with_tiles.w.partition.updateVertexPositions(makeDenseView(moved, Eigen::Vector3d::Zero()));
    const Eigen::Vector2d shifted = *marked + Eigen::Vector2d(3.0, -2.0);
    EXPECT_TRUE(det.isDynamic(MotionKind::Slow, with_tiles.w.partition, shifted));
    EXPECT_FALSE(det.isDynamic(MotionKind::Slow, with_tiles.w.partition, *marked + Eigen::Vector2d(0.0, 5.0)));

    // A saved and reloaded detector reads the same marks.
    mrpt::io::CMemoryStream mem;
    auto ar = mrpt::serialization::archiveFrom(mem);
    det.saveState(ar);
    mem.Seek(0);
    MotionDetector loaded(o);
    loaded.loadState(ar);
    EXPECT_EQ(loaded.tiles(), det.tiles());
    EXPECT_EQ(loaded.markedCells(MotionKind::Slow), det.markedCells(MotionKind::Slow));
    EXPECT_TRUE(loaded.isDynamic(MotionKind::Slow, with_tiles.w.partition, shifted));

    // Tiles go with their anchor region.
    std::vector<long> anchors;
    for (const auto& key : with_tiles.map.fallbackTileKeys()) anchors.push_back(key.anchor);
    with_tiles.map.removeRegions(anchors);
    det.removeRegions(anchors);
    EXPECT_EQ(det.tiles(), 0u);
    EXPECT_FALSE(det.isDynamic(MotionKind::Slow, with_tiles.w.partition, shifted));
    loaded.removeStaleRegions(with_tiles.map);
    EXPECT_EQ(loaded.tiles(), 0u);
    EXPECT_EQ(loaded.markedCells(MotionKind::Slow), det.markedCells(MotionKind::Slow));
}

// With the map's tiles in the rigid frame the marks are drawn where the map draws the
// tiles, also once the landmarks moved non-rigidly (where the affine frame differs).
TEST(MotionDetector, TileMarksFollowTheMapsFallbackFrame)
{
    MotionDetector::Options o;
    o.enable_fast = false;
    o.slow_period_s = 20.0;
    TileScene sc(hymm::dense::FallbackFrame::Rigid);
    MotionDetector det(o);
    sc.run(det, true);
    ASSERT_TRUE(sc.markedPoint(det).has_value());
    std::mt19937 rng(3);
    std::normal_distribution<double> n(0.0, 0.3);
    std::map<long, Eigen::Vector2d> jittered = sc.w.lattice.landmarks();
    for (auto& [id, q] : jittered)
    {
        const double dx = n(rng);  // two statements: argument order is unspecified
        q += Eigen::Vector2d(dx, n(rng));
    }
    sc.w.partition.updateVertexPositions(makeDenseView(jittered, Eigen::Vector3d::Zero()));
    const auto& p = sc.w.partition;
    std::set<long> anchors;
    for (const auto& key : sc.map.fallbackTileKeys()) anchors.insert(key.anchor);
    size_t checked = 0;
    for (const long anchor : anchors)
    {
        const auto marked = det.markedTileTriangles(p, {anchor});
        const auto to_current = sc.map.fallbackToCurrent(p, anchor);
        ASSERT_TRUE(to_current.has_value());
        const auto affine = hymm::dense::usableReferenceToCurrent(p, anchor);
        for (const auto& tri : marked)
        {
            const auto ref = to_current->inverseMapPoint(tri[0]);
            const auto key = hymm::dense::fallbackTileOf(anchor, (ref + to_current->inverseMapPoint(tri[1]) +
                                                                  to_current->inverseMapPoint(tri[2])) / 3.0,
                                                         10.0);
            const auto expected = hymm::dense::currentFallbackTileTriangle(key, 10.0, *to_current);
            const auto as_affine = hymm::dense::currentFallbackTileTriangle(key, 10.0, *affine);
            for (size_t v = 0; v < 3; ++v) EXPECT_LT((tri[v] - expected[v]).norm(), 1e-9);
            // The two frames differ here, so the check above can tell them apart.
            EXPECT_GT((as_affine[0] - expected[0]).norm() + (as_affine[1] - expected[1]).norm(), 1e-3);
            ++checked;
        }
    }
    EXPECT_GT(checked, 0u);
}

// Tiles overlap regions; where a region holds a place its own layers judge it. Here the
// regions are never differenced, so only the tiles reaching into the lattice mark the
// removed inner box: their marks are there but no reader reports them.
TEST(MotionDetector, TileMarksInsideARegionAreLeftToTheRegion)
{
    MotionDetector::Options o;
    o.enable_fast = false;
    o.slow_period_s = 20.0;
    TileScene sc;
    MotionDetector det(o);
    sc.run(det, true, false, true);
    const auto& p = sc.w.partition;
    // A tile holds a mark on the inner box's near face (x = 8), which a region holds.
    std::optional<Eigen::Vector2d> tile_mark;
    for (const auto& key : sc.map.fallbackTileKeys())
    {
        const auto* l = det.layer(MotionKind::Slow, key);
        if (!l || l->count() == 0) continue;
        const auto to_current = hymm::dense::usableReferenceToCurrent(p, key.anchor);
        ASSERT_TRUE(to_current.has_value());
        for (double y = 10.6; y < 13.4 && !tile_mark; y += 0.05)
            for (double x = 7.6; x < 10.4 && !tile_mark; x += 0.05)
            {
                const Eigen::Vector2d q(x, y), r = to_current->inverseMapPoint(q);
                if (hymm::dense::fallbackTileOf(key.anchor, r, 10.0) == key && l->at(r)) tile_mark = q;
            }
    }
    ASSERT_TRUE(tile_mark.has_value());
    EXPECT_FALSE(p.findRegions(*tile_mark).empty());
    EXPECT_FALSE(det.isDynamic(p, *tile_mark));
    EXPECT_FALSE(det.isDynamic(MotionKind::Slow, p, *tile_mark));
    mrpt::maps::COccupancyGridMap2D g(-5.0f, 25.0f, -5.0f, 30.0f, 0.1f);
    det.renderInto(MotionKind::Slow, p, g);
    for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
        for (unsigned cx = 0; cx < g.getSizeX(); ++cx)
        {
            if (g.getCell(cx, cy) <= 0.9f) continue;
            EXPECT_TRUE(p.findRegions(Eigen::Vector2d(g.idx2x(cx), g.idx2y(cy))).empty()) << cx << ' ' << cy;
        }
    // The container beyond the lattice is still found there.
    EXPECT_TRUE(sc.markedPoint(det).has_value());
    // With tile_marks_inside_regions the tile's mark is read there too.
    o.tile_marks_inside_regions = true;
    TileScene sc2;
    MotionDetector det2(o);
    sc2.run(det2, true, false, true);
    EXPECT_TRUE(det2.isDynamic(sc2.w.partition, *tile_mark));
}

// A wall in the tiles that moved by two cells between the slow snapshots is an edge that
// moved under the tiles' tolerance (3 cells), and motion without it.
TEST(MotionDetector, TilesTakeTheirOwnEdgeTolerance)
{
    const auto wallMarks = [](int tile_tolerance, bool& container_found) {
        MotionDetector::Options o;
        o.enable_fast = false;
        o.slow_period_s = 20.0;
        o.slow_tile_shift_tolerance_cells = tile_tolerance;
        TileScene sc;
        sc.wall_shift = 0.4;
        MotionDetector det(o);
        sc.run(det, true);
        container_found = sc.markedPoint(det).has_value();
        mrpt::maps::COccupancyGridMap2D g(-5.0f, 25.0f, -5.0f, 30.0f, 0.1f);
        det.renderInto(MotionKind::Slow, sc.w.partition, g);
        size_t n = 0;
        for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
            for (unsigned cx = 0; cx < g.getSizeX(); ++cx)
                if (g.getCell(cx, cy) > 0.9f && g.idx2y(cy) > 21.0) ++n;
        return n;
    };
    bool found_default = false, found_none = false;
    EXPECT_EQ(wallMarks(MotionDetector::Options{}.slow_tile_shift_tolerance_cells, found_default), 0u);
    EXPECT_GT(wallMarks(0, found_none), 10u);
    EXPECT_TRUE(found_default);
    EXPECT_TRUE(found_none);
}

TEST(MotionDetectorOptions, ReadsValidatesAndRejectsUnknownKeys)
{
    mrpt::config::CConfigFileMemory cfg("[MotionDetector]\nfast_period_s = 0.5\nlowpass = false\n");
    MotionDetector::Options o;
    o.loadFromConfigFile(cfg, "MotionDetector");
    EXPECT_DOUBLE_EQ(o.fast_period_s, 0.5);
    EXPECT_FALSE(o.lowpass);
    EXPECT_DOUBLE_EQ(o.slow_period_s, 150.0);
    mrpt::config::CConfigFileMemory typo("[MotionDetector]\nfast_perod_s = 0.5\n");
    EXPECT_THROW(o.loadFromConfigFile(typo, "MotionDetector"), std::invalid_argument);
    mrpt::config::CConfigFileMemory bad("[MotionDetector]\nthreshold = 1.5\n");
    EXPECT_THROW(o.loadFromConfigFile(bad, "MotionDetector"), std::invalid_argument);
    mrpt::config::CConfigFileMemory no_cluster("[MotionDetector]\nslow_min_cluster_cells = 0\n");
    EXPECT_THROW(o.loadFromConfigFile(no_cluster, "MotionDetector"), std::invalid_argument);
    // Round trip.
    mrpt::config::CConfigFileMemory out;
    o = MotionDetector::Options{};
    o.slow_period_s = 42;
    o.slow_min_cluster_cells = 4;
    o.fast_min_cluster_cells = 2;
    o.saveToConfigFile(out, "MotionDetector");
    MotionDetector::Options back;
    back.loadFromConfigFile(out, "MotionDetector");
    EXPECT_DOUBLE_EQ(back.slow_period_s, 42.0);
    EXPECT_EQ(back.slow_min_cluster_cells, 4);
    EXPECT_EQ(back.fast_min_cluster_cells, 2);
}

}  // namespace
