#include <gtest/gtest.h>
#include <hymm/eval/se2_alignment.h>

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

}  // namespace
