/**
 * @file matchers_test.cpp
 * @brief The three matchers on simulated pairs of scans of known polygons: convergence
 *        from an initial error, covariance consistency (mean NEES of the alignment error
 *        over many independent trials inside the chi-square band) and bad input.
 */
#include <gtest/gtest.h>
#include <hymm/scanslam/ScanMatcher.h>
#include <hymm/scanslam/Segmenter.h>
#include <mrpt/math/distributions.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/random/RandomGenerators.h>

#include <Eigen/Cholesky>
#include <cstdio>
#include <vector>
#include <cmath>

#include "sim_scenes.h"

using namespace hymm::scanslam;
using namespace hymm::scanslam::testing;

namespace
{
/** A template from the scan at pose A and the scan at pose B of the same world, with
 *  the true pose of the template frame in B's sensor frame. */
struct Pair
{
    ScanTemplate tpl;
    PointSet scan;
    Vec3 truth;
};

bool makePair(const hymm::sim::World& world, const Vec3& a, const Vec3& b, uint32_t seed,
              size_t which, Pair& out)
{
    // Thesis Table 5.1 laser (the regime the default cov_inflation was measured in, on
    // other worlds: benchmarks/scan_matchers).
    const Laser laser{0.1, 1.0, 30, 0.5};
    const PointSet sa = simulate(world, a, seed, laser);
    Segmenter::Options so;
    so.min_points = 15;
    so.max_range_gap_m = 1.0;
    const auto segs = Segmenter(so).segment(sa);
    if (segs.size() <= which) return false;
    out.tpl = ScanTemplate::fromSegment(sa, segs[which]);
    out.scan = simulate(world, b, seed + 500, laser);
    out.truth = compose(inverse(b), compose(a, out.tpl.frame_in_sensor));
    return true;
}

/** An L-shaped object (box seen corner-on) and a second box: well-conditioned. */
hymm::sim::World lWorld()
{
    std::vector<hymm::sim::WorldObject> objs;
    objs.push_back(fixedObject(0, box(4, 3), 8, 2, 1.03));
    objs.push_back(fixedObject(1, box(3, 2), 7, -5, -0.4));
    return hymm::sim::World({}, std::move(objs));
}

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

TEST_P(MatcherTest, CovarianceIsWithinAFactorOfConsistentOverManyDraws)
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
