/**
 * @file AffineRegionMap_test.cpp
 */
#include "hymm/ltr/AffineRegionMap.h"

#include <gtest/gtest.h>

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

}  // namespace
