#include <gtest/gtest.h>
#include <hymm/eval/nees.h>
#include <mrpt/math/distributions.h>

#include <cmath>
#include <limits>

namespace
{
using namespace hymm::eval;

TEST(NeesTest, MatchesHandComputedValues)
{
    EXPECT_NEAR(nees(Eigen::VectorXd::Constant(1, 2.0), Eigen::MatrixXd::Constant(1, 1, 4.0)).value,
                1.0, 1e-12);
    Eigen::VectorXd e(2);
    e << 1, 2;
    Eigen::MatrixXd P(2, 2);
    P << 1, 0, 0, 4;
    EXPECT_NEAR(nees(e, P).value, 2.0, 1e-12);
    // Correlated: P^-1 = [[2, -1], [-1, 2]] / 3, so e = (1, 0) gives 2/3.
    P << 2, 1, 1, 2;
    e << 1, 0;
    const auto v = nees(e, P);
    EXPECT_TRUE(v.ok());
    EXPECT_NEAR(v.value, 2.0 / 3.0, 1e-12);
}

TEST(NeesTest, SingularAndNonFiniteCovariancesAreReported)
{
    Eigen::VectorXd e(2);
    e << 1, 0;
    Eigen::MatrixXd P(2, 2);
    P << 1, 1, 1, 1;  // rank 1
    EXPECT_EQ(nees(e, P).status, NeesStatus::Singular);
    EXPECT_TRUE(std::isnan(nees(e, P).value));
    P << -1, 0, 0, 1;  // indefinite
    EXPECT_EQ(nees(e, P).status, NeesStatus::Singular);
    P << 1, 0, 0, std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(nees(e, P).status, NeesStatus::NotFinite);
    EXPECT_THROW(nees(e, Eigen::MatrixXd::Identity(3, 3)), std::invalid_argument);
}

TEST(NeesTest, ChiSquareQuantilesMatchTables)
{
    EXPECT_NEAR(chi2Quantile(0.975, 3), 9.348404, 1e-5);
    EXPECT_NEAR(chi2Quantile(0.025, 3), 0.2157953, 1e-6);
    EXPECT_NEAR(chi2Quantile(0.95, 2), 5.991465, 1e-5);
    EXPECT_NEAR(chi2Quantile(0.05, 1), 0.00393214, 1e-7);
    EXPECT_NEAR(chi2Quantile(0.99, 10), 23.20925, 1e-4);
    EXPECT_NEAR(chi2Quantile(0.975, 100), 129.5612, 1e-3);
    EXPECT_NEAR(chi2Quantile(0.025, 100), 74.22193, 1e-3);
    // Closed forms: 2 dof is exponential; 1 dof is a squared standard normal.
    for (double p : {0.001, 0.1, 0.5, 0.9, 0.999})
    {
        EXPECT_NEAR(chi2Quantile(p, 2), -2.0 * std::log(1.0 - p), 1e-9 * (1 - 2 * std::log(1 - p)));
        const double z = normalQuantile(0.5 * (1 + p));
        EXPECT_NEAR(chi2Quantile(p, 1), z * z, 1e-9 * (1 + z * z));
        EXPECT_NEAR(chi2Cdf(chi2Quantile(p, 7.0), 7.0), p, 1e-12);
    }
    EXPECT_NEAR(normalQuantile(0.975), 1.959963985, 1e-9);
    EXPECT_THROW(chi2Quantile(1.0, 3), std::invalid_argument);
    EXPECT_THROW(chi2Quantile(0.5, 0), std::invalid_argument);
}

TEST(NeesTest, MrptChi2invIsWilsonHilfertyGoodOnlyForLargeDof)
{
    for (unsigned dof : {3u, 10u, 100u, 1000u})
        for (double p : {0.025, 0.975})
        {
            const double mrpt_q = mrpt::math::chi2inv(p, dof);
            const double wh = chi2QuantileWilsonHilferty(p, dof);
            EXPECT_NEAR(mrpt_q / wh, 1.0, 1e-3) << "dof " << dof << " p " << p;
            if (dof >= 100)
            {
                EXPECT_NEAR(mrpt_q / chi2Quantile(p, dof), 1.0, 1e-3) << "dof " << dof;
            }
        }
    // Small dof, lower tail: off by more than 10% (and negative for one dof), which is why
    // the bounds use the exact quantile.
    EXPECT_GT(std::abs(mrpt::math::chi2inv(0.025, 3) / chi2Quantile(0.025, 3) - 1.0), 0.1);
    EXPECT_LT(mrpt::math::chi2inv(0.025, 1), 0.0);
}

TEST(NeesTest, AverageNeesBoundsScaleWithRuns)
{
    const auto one = averageNeesBounds(3, 1, 0.95);
    EXPECT_NEAR(one.lower, 0.2157953, 1e-6);
    EXPECT_NEAR(one.upper, 9.348404, 1e-5);
    const auto fifty = averageNeesBounds(2, 50, 0.95);
    EXPECT_NEAR(fifty.lower, 74.22193 / 50, 1e-4);
    EXPECT_NEAR(fifty.upper, 129.5612 / 50, 1e-4);
    EXPECT_TRUE(fifty.contains(2.0));
    EXPECT_FALSE(fifty.contains(1.0));
    EXPECT_THROW(averageNeesBounds(0, 5, 0.95), std::invalid_argument);
    EXPECT_THROW(averageNeesBounds(2, 5, 1.5), std::invalid_argument);
}

TEST(NeesTest, FractionInsideIgnoresMissingSteps)
{
    const NeesBounds b{0.5, 2.5};
    EXPECT_DOUBLE_EQ(
        fractionInsideBounds({1.0, 2.0, 3.0, std::numeric_limits<double>::quiet_NaN(), 0.1}, b), 0.5);
    EXPECT_TRUE(std::isnan(fractionInsideBounds({}, b)));
}

}  // namespace
