/**
 * @file ParticlesFreeSpace_test.cpp
 * @brief The particle layer's free-space step (thesis Sec. 4.2.2) with beams that return
 *        nothing and its protection, on a ray-cast scene against the true outlines:
 *        an object removed and re-observed through no-return beams loses its
 *        particles; a wall seen at grazing incidence and a wall partly hidden behind a
 *        new nearer object keep their weight (they do not without the protection).
 */
#include "hymm/dense/HybridMetricMap.h"

#include "hymm/dense/geometry.h"
#include "synthetic_partition.h"

#include <gtest/gtest.h>
#include <mrpt/maps/CPointsMapXYZI.h>

#include <array>
#include <cmath>
#include <iostream>
#include <optional>
#include <random>
#include <vector>

namespace
{
using namespace hymm::dense;
using namespace hymm::dense::synthetic;
using V2 = Eigen::Vector2d;
using Segment = std::array<V2, 2>;

constexpr double kLaserRange = 40.0;  // beyond: no return
constexpr int kBeams = 361;           // 0.5 deg over 180 deg
constexpr double kNoReturnRange = 20.0;

/** Closest hit of the ray from `o` along `u` on `segs` within the laser range. */
std::optional<double> castRay(const V2& o, const V2& u, const std::vector<Segment>& segs)
{
    std::optional<double> best;
    for (const Segment& s : segs)
    {
        const V2 e = s[1] - s[0];
        const double den = u.x() * e.y() - u.y() * e.x();
        if (std::abs(den) < 1e-12) continue;
        const V2 w = s[0] - o;
        const double t = (w.x() * e.y() - w.y() * e.x()) / den;
        const double v = (w.x() * u.y() - w.y() * u.x()) / den;
        if (t > 0 && t <= kLaserRange && v >= 0 && v <= 1 && (!best || t < *best)) best = t;
    }
    return best;
}

std::vector<Segment> box(double x0, double y0, double x1, double y1)
{
    return {{{V2(x0, y0), V2(x1, y0)}}, {{V2(x1, y0), V2(x1, y1)}}, {{V2(x1, y1), V2(x0, y1)}},
            {{V2(x0, y1), V2(x0, y0)}}};
}

/** The scene (lattice of 8 x 6 landmarks 5 m apart: regions over [0, 35] x [0, 25]):
 *  the vehicle at (2..3.6, 12.5) looks east along
 *  - a grazing wall G, y = 10.5 for x in [6, 24]; its far part, x in [14, 24], is seen
 *    at 5-10 deg incidence: consecutive returns lie 0.6-2.1 m apart along it, more
 *    than 2 d_min, and the beams past its end return nothing;
 *  - an object A, [10, 11.5] x [19, 20.5], removed for the second phase: nothing lies
 *    behind it within the laser range, so its place is then seen against nothing;
 *  - a wall C, x = 20 for y in [15.5, 19], partly hidden in the second phase behind a
 *    new object B, [14, 14.6] x [15.2, 16.9]: from every pose B's shadow covers C from
 *    y = 16.6 to past its end, and the beams just past B's upper edge return nothing
 *    (they pass 0.1-0.45 m beyond C's end), so their cones reach C's hidden end. */
const std::vector<Segment> kGrazingWall = {{{V2(6, 10.5), V2(24, 10.5)}}};
const std::vector<Segment> kRemoved = box(10, 19, 11.5, 20.5);
const std::vector<Segment> kHiddenWall = {{{V2(20, 15.5), V2(20, 19)}}};
const std::vector<Segment> kOccluder = box(14, 15.2, 14.6, 16.9);

std::vector<Segment> scene(bool second_phase)
{
    std::vector<Segment> s = kGrazingWall;
    s.insert(s.end(), kHiddenWall.begin(), kHiddenWall.end());
    const auto& extra = second_phase ? kOccluder : kRemoved;
    s.insert(s.end(), extra.begin(), extra.end());
    return s;
}

mrpt::math::TPose2D pose(int k) { return {2.0 + 0.4 * (k % 5), 12.5, 0.0}; }

/** A scan at `vehicle` (sensor on the vehicle origin) with 2 cm range noise. */
ScanPoints scanAt(const mrpt::math::TPose2D& vehicle, const std::vector<Segment>& segs, std::mt19937& rng)
{
    std::normal_distribution<double> n01(0.0, 1.0);
    ScanPoints s;
    for (int i = 0; i < kBeams; ++i)
    {
        const double a = -M_PI / 2 + M_PI * i / (kBeams - 1.0);
        const V2 u(std::cos(vehicle.phi + a), std::sin(vehicle.phi + a));
        const auto r = castRay(V2(vehicle.x, vehicle.y), u, segs);
        if (r)
            s.points.push_back((*r + 0.02 * n01(rng)) * V2(std::cos(a), std::sin(a)));
        else
            s.no_return_bearings.push_back(a);
    }
    return s;
}

struct Counts
{
    size_t removed = 0, grazing = 0, hidden = 0;
};

/** Heavy particles (w > 0.8) within 0.3 m of each part of the scene. */
Counts heavyNear(const HybridMetricMap& map, const hymm::ltr::RegionPartition& partition)
{
    mrpt::maps::CPointsMapXYZI pts;
    map.renderLayer(ParticlesLayer::kKind, partition, pts);
    const auto near = [](const V2& p, const std::vector<Segment>& segs) {
        for (const Segment& s : segs)
            if (distanceToSegment(p, s[0], s[1]) <= 0.3) return true;
        return false;
    };
    // The hidden end of C, next to the no-return beams past B and 1.6 m from the
    // visible part of C (the samples drawn around visible returns, Eq. 4.8, spread
    // about 0.3 m per bearing sigma there and update what they fall on: the sensor
    // model, not the free-space step), and the far part of the grazing wall where
    // returns are sparse.
    const std::vector<Segment> hidden = {{{V2(20, 18.5), V2(20, 19)}}};
    const std::vector<Segment> grazing_far = {{{V2(14, 10.5), V2(24, 10.5)}}};
    Counts c;
    for (size_t i = 0; i < pts.size(); ++i)
    {
        if (pts.getPointIntensity(i) <= 0.8f) continue;
        const V2 p(pts.getPointsBufferRef_x()[i], pts.getPointsBufferRef_y()[i]);
        c.removed += near(p, kRemoved);
        c.grazing += near(p, grazing_far);
        c.hidden += near(p, hidden);
    }
    return c;
}

struct Outcome
{
    Counts before, after;
    size_t protected_last = 0;
};

Outcome simulate(double no_return_free_range_m, bool protection)
{
    const Lattice lattice{8, 6, 5.0, V2(0, 0)};
    const IndependentLandmarksView view(lattice.landmarks());
    hymm::ltr::RegionPartition partition(permissivePartitionOptions());
    addRegions(partition, view, lattice.triangles(V2(17.5, 12.5)), 70);
    HybridMetricMap::Options o;
    o.enable_points = o.enable_occupancy = false;
    o.enable_particles = true;
    o.no_return_free_range_m = no_return_free_range_m;
    o.particles.free_space_protection = protection;
    HybridMetricMap map(o);
    std::mt19937 rng(5);
    Outcome run;
    for (int k = 0; k < 15; ++k) map.insertScan(scanAt(pose(k), scene(false), rng), pose(k), partition);
    run.before = heavyNear(map, partition);
    for (int k = 0; k < 30; ++k)
    {
        map.insertScan(scanAt(pose(k), scene(true), rng), pose(k), partition);
        for (const long id : map.regionIds())
            run.protected_last +=
                map.localMap(id)->layerAs<ParticlesLayer>(ParticlesLayer::kKind)->lastUpdate().free_protected;
    }
    run.after = heavyNear(map, partition);
    return run;
}

void print(const char* what, const Outcome& r)
{
    std::cout << "[ particles ] " << what << ": removed object " << r.before.removed << " -> "
              << r.after.removed << ", grazing wall " << r.before.grazing << " -> " << r.after.grazing
              << ", hidden wall " << r.before.hidden << " -> " << r.after.hidden
              << " (protected particle updates in phase 2: " << r.protected_last << ")\n";
}

TEST(ParticlesFreeSpaceTest, NoReturnBeamsEmptyAVacatedPlaceAndTheProtectionKeepsWhatStayed)
{
    const Outcome on = simulate(kNoReturnRange, true);
    const Outcome off = simulate(0.0, true);
    const Outcome unprotected = simulate(kNoReturnRange, false);
    const Outcome neither = simulate(0.0, false);  // the step before no-return beams
    print("no-return on,  protection on ", on);
    print("no-return off, protection on ", off);
    print("no-return on,  protection off", unprotected);
    print("no-return off, protection off", neither);

    // Phase 1 built every surface.
    for (const Outcome* r : {&on, &off})
    {
        EXPECT_GT(r->before.removed, 300u);
        EXPECT_GT(r->before.grazing, 300u);
        EXPECT_GT(r->before.hidden, 100u);
    }
    // (a) The removed object, seen against nothing: only the no-return beams free it.
    EXPECT_LE(on.after.removed, on.before.removed / 50);
    EXPECT_GE(off.after.removed, off.before.removed * 9 / 10);
    // (b) The grazing wall and the wall behind the new object keep their weight...
    EXPECT_GE(on.after.grazing, on.before.grazing * 9 / 10);
    EXPECT_GE(on.after.hidden, on.before.hidden * 9 / 10);
    EXPECT_GT(on.protected_last, 0u);
    // ... which they do not without the protection (the test can tell): the no-return
    // beams past the ends of both walls sweep them.
    EXPECT_LT(unprotected.after.grazing, on.after.grazing * 7 / 10);
    EXPECT_LT(unprotected.after.hidden, on.after.hidden * 7 / 10);
}

}  // namespace
