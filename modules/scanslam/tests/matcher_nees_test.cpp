/**
 * @file matcher_nees_test.cpp
 * @brief Covariance consistency of the three matchers: NEES of the alignment error
 *        against the truth over 1,200 simulated pairs per matcher. Its own executable
 *        (ctest label 'long'): 10 s in Release, ~9 min under the sanitizers, where the
 *        matchers' small fixed-size Eigen code runs far slower; the sanitizer stage covers
 *        the same code through matchers_test.cpp.
 */
#include <gtest/gtest.h>
#include <mrpt/math/distributions.h>
#include <mrpt/random/RandomGenerators.h>

#include <Eigen/Cholesky>
#include <cstdio>
#include <string>
#include <vector>

#include "matcher_pairs.h"

using namespace hymm::scanslam;
using namespace hymm::scanslam::testing;

namespace
{
class MatcherNeesTest : public ::testing::TestWithParam<std::string>
{
};
}  // namespace

/** NEES of the alignment error against the truth for `trials` random pairs drawn from
 *  `rng` (converged alignments only). */
static std::vector<double> neesOverTrials(const ScanMatcher& matcher, const hymm::sim::World& world,
                                          mrpt::random::CRandomGenerator& rng, uint32_t noise_seed,
                                          int trials)
{
    std::vector<double> nees;
    for (int t = 0; t < trials; ++t)
    {
        // Random viewpoints around a nominal pair; each trial draws new noise for both
        // template and scan.
        // One draw per statement, last component first: the order GCC evaluated the
        // former one-line argument lists in (clang's order gave other trials).
        const auto draw3 = [&](double xy, double phi, bool gaussian) {
            Vec3 v;
            for (int i = 2; i >= 0; --i)
            {
                const double s = i == 2 ? phi : xy;
                v[i] = gaussian ? s * rng.drawGaussian1D_normalized() : rng.drawUniform(-s, s);
            }
            return v;
        };
        const Vec3 a = draw3(1.0, 0.1, false);
        const Vec3 b = draw3(1.0, 0.1, false);
        Pair p;
        if (!makePair(world, a, b, noise_seed + 7 * t, t % 2, p)) continue;
        const Vec3 z0 = p.truth + draw3(0.1, 0.01, true);
        const AlignResult r = matcher.align(p.tpl.sog, p.scan, z0);
        if (!r.ok) continue;
        const Vec3 e = poseDifference(r.z, p.truth);
        nees.push_back(e.dot(r.R.ldlt().solve(e)));
    }
    return nees;
}

TEST_P(MatcherNeesTest, CovarianceIsWithinAFactorOfConsistentOverManyDraws)
{
    // Twenty independent draws of 60 pairs each, pooled. One draw of 60 cannot judge a
    // covariance: the errors are heavier-tailed than a Gaussian (the template and the
    // scan sample the faces at other places), so the mean NEES of one draw spans
    // 2.8-9.0 for SOG, 2.0-4.0 for ICP and 2.4-3.7 for the correlative matcher over these
    // 20, and whether it fell inside the 99 % band of 60 chi-square(3) values depended
    // on the draw (docs/benchmarks.md, "Scan matchers"). Pooled, each matcher has its
    // own value on this world: SOG 4.3 (1.4x over-confident: its default cov_inflation
    // 1.0 was measured on smaller viewpoint changes), ICP 2.7, correlative 3.0. The test
    // pins the covariances to within a factor 1.5 of consistent here, and bounds the
    // tail: at most 10 % of the alignments beyond the 99 % gate (a consistent R: 1 %).
    const auto matcher = makeMatcher(GetParam());
    const auto world = lWorld();
    std::vector<double> all;
    for (uint32_t draw = 0; draw < 20; ++draw)
    {
        mrpt::random::CRandomGenerator rng(4 + 1000 * draw);
        const auto nees = neesOverTrials(*matcher, world, rng, 2000 + 100000 * draw, 60);
        ASSERT_GE(nees.size(), 50u) << "draw " << draw;
        all.insert(all.end(), nees.begin(), nees.end());
    }
    double sum = 0;
    size_t beyond_gate = 0;
    const double gate99 = mrpt::math::chi2inv(0.99, 3);
    for (const double v : all)
    {
        sum += v;
        beyond_gate += v > gate99 ? 1 : 0;
    }
    const double mean = sum / static_cast<double>(all.size());
    const double tail = static_cast<double>(beyond_gate) / static_cast<double>(all.size());
    EXPECT_GT(mean, 3.0 / 1.5) << GetParam() << " pooled mean NEES " << mean;
    EXPECT_LT(mean, 3.0 * 1.5) << GetParam() << " pooled mean NEES " << mean;
    EXPECT_LT(tail, 0.10) << GetParam() << " beyond the 99 % gate " << tail;
    std::printf("%s: %zu alignments, mean NEES %.3f, beyond the 99 %% gate %.3f\n", GetParam().c_str(),
                all.size(), mean, tail);
}

INSTANTIATE_TEST_SUITE_P(AllMatchers, MatcherNeesTest, ::testing::Values("sog", "icp", "correlative"),
                         [](const auto& pinfo) { return pinfo.param; });
