/**
 * @file matchers_test.cpp
 * @brief The three matchers on simulated pairs of scans of known polygons: convergence
 *        from an initial error and bad input (covariance consistency:
 *        matcher_nees_test.cpp).
 */
#include <gtest/gtest.h>
#include <hymm/scanslam/ScanMatcher.h>
#include <hymm/scanslam/Segmenter.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/random/RandomGenerators.h>

#include <cmath>
#include <tuple>
#include <vector>

#include "../src/LikelihoodGrid.h"
#include "matcher_pairs.h"

using namespace hymm::scanslam;
using namespace hymm::scanslam::testing;

namespace
{
class MatcherTest : public ::testing::TestWithParam<std::string>
{
};
}  // namespace

TEST_P(MatcherTest, ConvergesFromAnInitialError)
{
    const auto matcher = makeMatcher(GetParam());
    const auto world = lWorld();
    mrpt::random::CRandomGenerator rng(3);
    int good = 0;
    const int n = 10;
    for (int t = 0; t < n; ++t)
    {
        Pair p;
        // Segment 1 (scan order is right to left): the box seen corner-on.
        ASSERT_TRUE(makePair(world, Vec3::Zero(), Vec3(0.5, 0.3, 0.05), 100 + t, 1, p));
        ASSERT_GT(p.tpl.sog.size(), 50u);
        // 0.4 m and 4.6 deg off in a random direction.
        const double a = rng.drawUniform(-M_PI, M_PI);
        const Vec3 z0 = p.truth + Vec3(0.4 * std::cos(a), 0.4 * std::sin(a), t % 2 ? 0.08 : -0.08);
        const AlignResult r = matcher->align(p.tpl.sog, p.scan, z0);
        if (!r.ok) continue;
        // Converged: near the truth, or back to the solution the matcher finds from the
        // truth itself (the data's own error reaches a few cm and 2-3 deg here).
        const Vec3 et = poseDifference(r.z, p.truth);
        const AlignResult ref = matcher->align(p.tpl.sog, p.scan, p.truth);
        const Vec3 e = poseDifference(r.z, ref.z);
        if ((et.head<2>().norm() < 0.2 && std::abs(et.z()) < 0.035) ||
            (ref.ok && e.head<2>().norm() < 0.05 && std::abs(e.z()) < 0.02))
            ++good;
    }
    EXPECT_GE(good, 9) << GetParam();
}

TEST_P(MatcherTest, BadInputFailsCleanly)
{
    const auto matcher = makeMatcher(GetParam());
    const auto world = lWorld();
    Pair p;
    ASSERT_TRUE(makePair(world, Vec3::Zero(), Vec3::Zero(), 9, 0, p));
    EXPECT_FALSE(matcher->align(p.tpl.sog, PointSet{}, p.truth).ok);
    EXPECT_FALSE(matcher->align(PointSet{}, p.scan, p.truth).ok);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(matcher->align(p.tpl.sog, p.scan, Vec3(nan, 0, 0)).ok);
    // Far from any return: no result rather than a made-up one.
    const AlignResult far = matcher->align(p.tpl.sog, p.scan, Vec3(-20, 0, 0));
    EXPECT_FALSE(far.ok);
    // Whatever comes back is finite.
    const AlignResult r = matcher->align(p.tpl.sog, p.scan, p.truth);
    ASSERT_TRUE(r.ok);
    EXPECT_TRUE(r.z.allFinite() && r.R.allFinite());
}

INSTANTIATE_TEST_SUITE_P(AllMatchers, MatcherTest,
                         ::testing::Values("sog", "icp", "correlative"),
                         [](const auto& pinfo) { return pinfo.param; });

TEST(MatcherFactoryTest, UnknownNamesAndKeysThrow)
{
    EXPECT_THROW(makeMatcher("ndt"), std::invalid_argument);
    mrpt::config::CConfigFileMemory cfg("[M]\nscales_m = 0.3 0\ncov_inflation = 2\n");
    EXPECT_EQ(makeMatcher("sog", &cfg, "M")->name(), "sog");
    EXPECT_THROW(makeMatcher("icp", &cfg, "M"), std::exception);  // scales_m is not an ICP key
}

// The exhaustive searches (correlative matcher, wide search) score a lattice of
// translations at once (LikelihoodGrid::scoreLattice). Each score must be the sum of the
// bilinear lookups of the pose, point by point: the figures measured with the per-pose
// loop stand only if it is. Points near the edge take the per-pose path, the others the
// shared rows; both are checked, on steps finer and coarser than a cell.
TEST(LikelihoodGridTest, LatticeScoresAreThePerPoseSums)
{
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(11);
    PointSet scan;
    for (int k = 0; k < 300; ++k)
        scan.add(Vec2(rng.drawUniform(-4, 4), rng.drawUniform(-3, 3)), Mat2::Identity() * 1e-4);
    const LikelihoodGrid grid(Vec2(-5, -4), Vec2(5, 4), 0.1, 0.15, 3.0, scan);
    std::vector<Vec2> pts;
    for (int k = 0; k < 60; ++k) pts.emplace_back(rng.drawUniform(-3, 3), rng.drawUniform(-2, 2));
    pts.emplace_back(4.93, 0.0);   // beyond the grid for some translations: the per-pose path
    pts.emplace_back(0.0, -3.97);
    size_t inside_floor = 0;
    for (const auto& [cx, cy, step, nx, ny] :
         {std::tuple{0.013, -0.021, 0.01, 10, 10}, std::tuple{0.3, 0.2, 0.1, 4, 6}, std::tuple{-0.1, 0.05, 0.23, 5, 3}})
    {
        std::vector<double> out;
        grid.scoreLattice(pts, cx, cy, step, nx, ny, out);
        ASSERT_EQ(out.size(), static_cast<size_t>((2 * nx + 1) * (2 * ny + 1)));
        for (int ky = -ny; ky <= ny; ++ky)
            for (int kx = -nx; kx <= nx; ++kx)
            {
                const double tx = cx + kx * step, ty = cy + ky * step;
                double s = 0;
                for (const Vec2& p : pts) s += grid.at(p.x() + tx, p.y() + ty);
                const double got = out[static_cast<size_t>((ky + ny) * (2 * nx + 1) + kx + nx)];
                EXPECT_NEAR(got, s, 1e-12 * (1 + std::abs(s))) << "kx " << kx << " ky " << ky << " step " << step;
                inside_floor += got > grid.floorValue() * static_cast<double>(pts.size());
            }
    }
    EXPECT_GT(inside_floor, 0u);  // the lattices do reach the scan
}
