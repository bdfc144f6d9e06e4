/**
 * @file AffineRegionMap_test.cpp
 */
#include "hymm/ltr/AffineRegionMap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace
{
using hymm::ltr::AffineRegionMap;
using hymm::ltr::TriangleFrame;
using V2 = Eigen::Vector2d;

TriangleFrame randomFrame(std::mt19937& rng)
{
    std::uniform_real_distribution<double> u(-20, 20);
    for (;;)
    {
        const auto f = TriangleFrame::tryCreate(
            {V2(u(rng), u(rng)), V2(u(rng), u(rng)), V2(u(rng), u(rng))}, {5.0, 50.0});
        if (f) return *f;
    }
}

TEST(AffineRegionMapTest, KeepsBarycentricCoordinates)
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 2);
    for (int t = 0; t < 100; ++t)
    {
        const TriangleFrame ref = randomFrame(rng), cur = randomFrame(rng);
        const AffineRegionMap m(ref, cur);
        for (int k = 0; k < 3; ++k)
            EXPECT_LT((m.mapPoint(ref.vertex(k)) - cur.vertex(k)).norm(), 1e-9);
        const V2 l(u(rng), u(rng));
        const V2 p_ref = ref.toGlobal(l);
        EXPECT_LT((cur.toLocal(m.mapPoint(p_ref)) - l).norm(), 1e-9);
    }
}

TEST(AffineRegionMapTest, DirectionsAndInverse)
{
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(-10, 10);
    for (int t = 0; t < 100; ++t)
    {
        const TriangleFrame ref = randomFrame(rng), cur = randomFrame(rng);
        const AffineRegionMap m(ref, cur);
        const V2 p(u(rng), u(rng)), q(u(rng), u(rng));
        EXPECT_LT((m.mapDirection(q - p) - (m.mapPoint(q) - m.mapPoint(p))).norm(), 1e-9);
        EXPECT_LT((m.inverseMapPoint(m.mapPoint(p)) - p).norm(), 1e-9);
        EXPECT_LT((m.inverseMapDirection(m.mapDirection(q)) - q).norm(), 1e-9);
        const AffineRegionMap inv = m.inverse();
        EXPECT_LT((inv.mapPoint(p) - m.inverseMapPoint(p)).norm(), 1e-9);
        EXPECT_LT((inv.inverse().mapPoint(p) - m.mapPoint(p)).norm(), 1e-9);
        // The inverse of reference->current is current->reference.
        EXPECT_LT((inv.mapPoint(p) - AffineRegionMap(cur, ref).mapPoint(p)).norm(), 1e-9);
    }
}

TEST(AffineRegionMapTest, UnchangedTriangleGivesIdentity)
{
    std::mt19937 rng(13);
    const TriangleFrame f = randomFrame(rng);
    const AffineRegionMap m(f, f);
    EXPECT_TRUE(m.linear().isApprox(Eigen::Matrix2d::Identity(), 1e-12));
    EXPECT_LT(m.translation().norm(), 1e-9);
    EXPECT_TRUE(AffineRegionMap().mapPoint(V2(3, -4)).isApprox(V2(3, -4)));
}

// The sum of squared vertex residuals of the map p -> R(th) p + t.
double rigidCost(const TriangleFrame& ref, const TriangleFrame& cur, double th, const V2& t)
{
    Eigen::Matrix2d r;
    r << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
    double c = 0;
    for (int k = 0; k < 3; ++k) c += (r * ref.vertex(k) + t - cur.vertex(k)).squaredNorm();
    return c;
}

TEST(AffineRegionMapTest, RigidPartIsExactForARigidMoveAndTheBestFitOtherwise)
{
    std::mt19937 rng(14);
    std::uniform_real_distribution<double> u(-10, 10), ang(-3.1, 3.1), jitter(-1.5, 1.5);
    for (int t = 0; t < 100; ++t)
    {
        const TriangleFrame ref = randomFrame(rng);
        const double th = ang(rng);
        Eigen::Matrix2d r;
        r << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
        const V2 tr(u(rng), u(rng));
        TriangleFrame::Vertices moved = ref.vertices(), deformed = ref.vertices();
        for (size_t k = 0; k < 3; ++k)
        {
            moved[k] = r * moved[k] + tr;
            deformed[k] = moved[k] + V2(jitter(rng), jitter(rng));
        }
        // A rigid move: both maps agree everywhere, far outside the triangle too.
        const AffineRegionMap rigid_move(ref, TriangleFrame(moved));
        const AffineRegionMap rp = rigid_move.rigidPart(ref.vertices());
        for (const V2& p : {V2(u(rng), u(rng)), V2(100 * u(rng), 100 * u(rng))})
            EXPECT_LT((rp.mapPoint(p) - rigid_move.mapPoint(p)).norm(), 1e-8 * (1 + p.norm()));
        const auto def = TriangleFrame::tryCreate(deformed);
        if (!def) continue;
        const AffineRegionMap m(ref, *def);
        const AffineRegionMap fit = m.rigidPart(ref.vertices());
        // A rotation...
        EXPECT_TRUE((fit.linear().transpose() * fit.linear()).isApprox(Eigen::Matrix2d::Identity(), 1e-12));
        EXPECT_NEAR(fit.linear().determinant(), 1.0, 1e-12);
        // ...that fits the vertex pairs best: any small change of angle or translation costs.
        const double fth = std::atan2(fit.linear()(1, 0), fit.linear()(0, 0));
        const double c0 = rigidCost(ref, *def, fth, fit.translation());
        for (const double d : {-1e-3, 1e-3})
        {
            EXPECT_GT(rigidCost(ref, *def, fth + d, fit.translation()), c0);
            EXPECT_GT(rigidCost(ref, *def, fth, fit.translation() + V2(d, 0)), c0);
            EXPECT_GT(rigidCost(ref, *def, fth, fit.translation() + V2(0, d)), c0);
        }
        // Its own rigid part, and the inverse's, are consistent.
        const V2 p(u(rng), u(rng));
        EXPECT_LT((fit.rigidPart(ref.vertices()).mapPoint(p) - fit.mapPoint(p)).norm(), 1e-9);
        EXPECT_LT((m.inverse().rigidPart(def->vertices()).mapPoint(fit.mapPoint(p)) - p).norm(), 1e-9);
        // The fit of the swapped pairs (current -> reference) is this fit's inverse.
        EXPECT_LT((AffineRegionMap(*def, ref).rigidPart(def->vertices()).mapPoint(fit.mapPoint(p)) - p).norm(), 1e-9);
        EXPECT_LT((fit.inverseMapPoint(fit.mapPoint(p)) - p).norm(), 1e-9);
    }
    EXPECT_TRUE(AffineRegionMap().rigidPart({V2(0, 0), V2(1, 0), V2(0, 1)}).mapPoint(V2(3, -4)).isApprox(V2(3, -4)));
}

}  // namespace
