#include <gtest/gtest.h>
#include <hymm/eval/se2_alignment.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/tfest/se2.h>

#include <cstdio>
#include <random>

namespace
{
using namespace hymm::eval;

double cost(const Se2Transform& T, const std::vector<Eigen::Vector2d>& s,
            const std::vector<Eigen::Vector2d>& d)
{
    double c = 0;
    for (size_t i = 0; i < s.size(); ++i) c += (T.apply(s[i]) - d[i]).squaredNorm();
    return c;
}

TEST(Se2AlignmentTest, RecoversAKnownTransform)
{
    const Se2Transform truth{3.0, -2.0, 2.7};
    std::vector<Eigen::Vector2d> src = {{0, 0}, {1, 0}, {4, 3}, {-2, 5}, {7, -1}};
    std::vector<Eigen::Vector2d> dst;
    for (const auto& p : src) dst.push_back(truth.apply(p));
    const auto T = alignSE2(src, dst);
    ASSERT_TRUE(T.has_value());
    EXPECT_NEAR(T->x, 3.0, 1e-12);
    EXPECT_NEAR(T->y, -2.0, 1e-12);
    EXPECT_NEAR(T->phi, 2.7, 1e-12);
    const auto I = T->inverse();
    EXPECT_NEAR((I.apply(T->apply({1.5, -0.5})) - Eigen::Vector2d(1.5, -0.5)).norm(), 0, 1e-12);
}

TEST(Se2AlignmentTest, NoisyFitIsALeastSquaresMinimum)
{
    const Se2Transform truth{-1.0, 0.5, -0.4};
    std::mt19937 rng(7);
    std::normal_distribution<double> g(0, 0.1);
    std::vector<Eigen::Vector2d> src, dst;
    for (int i = 0; i < 30; ++i)
    {
        src.emplace_back(0.5 * i, std::sin(0.3 * i) * 4);
        dst.push_back(truth.apply(src.back()) + Eigen::Vector2d(g(rng), g(rng)));
    }
    const auto T = alignSE2(src, dst);
    ASSERT_TRUE(T.has_value());
    const double c0 = cost(*T, src, dst);
    for (const auto& d : {Se2Transform{1e-3, 0, 0}, Se2Transform{0, 1e-3, 0}, Se2Transform{0, 0, 1e-4}})
    {
        EXPECT_LT(c0, cost({T->x + d.x, T->y + d.y, T->phi + d.phi}, src, dst));
        EXPECT_LT(c0, cost({T->x - d.x, T->y - d.y, T->phi - d.phi}, src, dst));
    }
}

TEST(Se2AlignmentTest, DegenerateInputHasNoAlignment)
{
    EXPECT_FALSE(alignSE2({{1, 1}}, {{2, 2}}).has_value());
    EXPECT_FALSE(alignSE2({{1, 1}, {1, 1}}, {{2, 2}, {3, 3}}).has_value());
    EXPECT_FALSE(alignSE2({{1, 1}, {2, 1}}, {{2, 2}}).has_value());
}


TEST(Se2AlignmentTest, RotationJacobianMatchesNumericDifferentiation)
{
    const Se2Transform truth{2.0, 1.0, 0.3};
    std::mt19937 rng(11);
    std::normal_distribution<double> g(0, 0.2);
    std::vector<Eigen::Vector2d> src, dst;
    for (int i = 0; i < 12; ++i)
    {
        src.emplace_back(3.0 * std::cos(0.7 * i) + 0.4 * i, 2.0 * std::sin(1.1 * i));
        dst.push_back(truth.apply(src.back()) + Eigen::Vector2d(g(rng), g(rng)));
    }
    const auto J = alignSE2RotationJacobian(src, dst);
    ASSERT_TRUE(J.has_value());
    ASSERT_EQ(J->size(), 24);
    const double h = 1e-6;
    for (int k = 0; k < 24; ++k)
    {
        auto plus = src, minus = src;
        plus[k / 2][k % 2] += h;
        minus[k / 2][k % 2] -= h;
        const double numeric = (alignSE2(plus, dst)->phi - alignSE2(minus, dst)->phi) / (2 * h);
        EXPECT_NEAR((*J)(k), numeric, 1e-7) << "entry " << k;
    }
    EXPECT_FALSE(alignSE2RotationJacobian({{1, 1}, {1, 1}}, {{2, 2}, {3, 3}}).has_value());
}

TEST(Se2AlignmentTest, RotationVarianceMatchesMonteCarlo)
{
    // Independent isotropic noise on the source points: J P J^T must predict the spread
    // of the fitted rotation over many draws.
    std::vector<Eigen::Vector2d> base;
    for (int i = 0; i < 10; ++i) base.emplace_back(4.0 * i - 18.0, (i % 3) * 5.0 - 5.0);
    const double sigma = 0.3;
    const auto J = alignSE2RotationJacobian(base, base);
    ASSERT_TRUE(J.has_value());
    const double predicted = sigma * sigma * J->squaredNorm();
    std::mt19937 rng(3);
    std::normal_distribution<double> g(0, sigma);
    double sum2 = 0;
    const int draws = 4000;
    for (int n = 0; n < draws; ++n)
    {
        auto src = base;
        for (auto& p : src) p += Eigen::Vector2d(g(rng), g(rng));
        const double phi = alignSE2(src, base)->phi;
        sum2 += phi * phi;
    }
    EXPECT_NEAR(sum2 / draws / predicted, 1.0, 0.08);
}


// MRPT's mrpt::tfest::se2_l2 solves the same least squares; README ("Why not
// mrpt::tfest::se2_l2") explains why alignSE2 stays. Both agree near the origin; MRPT
// 2.5 takes the pairs as float (TMatchingPairList), so far from the origin (dataset
// coordinates, UTM) its result moves by what float rounding of the coordinates costs.
double se2Disagreement(double offset, double* dphi)
{
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0, 0.5);
    std::vector<Eigen::Vector2d> src, dst;
    mrpt::tfest::TMatchingPairList pairs;
    const double c = std::cos(0.3), s = std::sin(0.3);
    for (int i = 0; i < 469; ++i)
    {
        const double a = 2 * M_PI * i / 469;
        const Eigen::Vector2d d(offset + 40 * std::cos(a), offset + 40 * std::sin(a));
        src.emplace_back(c * d.x() - s * d.y() + 5 + g(rng), s * d.x() + c * d.y() - 3 + g(rng));
        dst.push_back(d);
        pairs.emplace_back(mrpt::tfest::TMatchingPair(
            i, i, static_cast<float>(d.x()), static_cast<float>(d.y()), 0.f,
            static_cast<float>(src.back().x()), static_cast<float>(src.back().y()), 0.f));
    }
    const auto ours = alignSE2(src, dst);
    mrpt::math::TPose2D theirs;
    EXPECT_TRUE(ours.has_value());
    EXPECT_TRUE(mrpt::tfest::se2_l2(pairs, theirs));
    *dphi = std::abs(std::remainder(ours->phi - theirs.phi, 2 * M_PI));
    // Disagreement where it matters: a transformed source point, in metres.
    double worst = 0;
    for (const auto& p : src)
    {
        const mrpt::math::TPoint2D q = theirs.composePoint(mrpt::math::TPoint2D(p.x(), p.y()));
        worst = std::max(worst, (ours->apply(p) - Eigen::Vector2d(q.x, q.y)).norm());
    }
    return worst;
}

TEST(Se2AlignmentTest, AgreesWithMrptSe2L2NearTheOriginOnly)
{
    double dphi = 0;
    const double near = se2Disagreement(0.0, &dphi);
    std::printf("se2_l2 vs alignSE2 at the origin: %.3g m, %.3g rad\n", near, dphi);
    EXPECT_LT(near, 1e-4);
    EXPECT_LT(dphi, 1e-5);
    // 5 km away (a UTM-like frame): float pairs cost millimetres to centimetres.
    const double far = se2Disagreement(5000.0, &dphi);
    std::printf("se2_l2 vs alignSE2 at 5 km: %.3g m, %.3g rad\n", far, dphi);
    EXPECT_GT(far, 100 * near);
    EXPECT_GT(far, 1e-4);
}

}  // namespace
