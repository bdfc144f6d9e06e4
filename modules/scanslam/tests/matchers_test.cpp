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
