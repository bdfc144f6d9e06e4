#include <gtest/gtest.h>
#include <hymm/extract/circle_fit.h>

#include <cmath>
#include <random>

namespace
{
using hymm::extract::fitCircle;

constexpr double kPi = 3.14159265358979323846;

std::vector<Eigen::Vector2d> arc(const Eigen::Vector2d& c, double r, double a0, double a1, int n,
                                 double noise = 0, unsigned seed = 1)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<Eigen::Vector2d> pts;
    for (int i = 0; i < n; ++i)
    {
        const double a = a0 + (a1 - a0) * i / (n - 1);
        const double rr = r + noise * g(rng);
        pts.push_back(c + rr * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
    return pts;
}

TEST(CircleFitTest, ExactPointsGiveTheExactCircleFarFromTheOrigin)
{
    const Eigen::Vector2d c(150.0, -320.0);
    const auto fit = fitCircle(arc(c, 0.35, 2.0, 3.5, 8));
    ASSERT_TRUE(fit.has_value());
    EXPECT_NEAR((fit->centre - c).norm(), 0.0, 1e-8);
    EXPECT_NEAR(fit->radius, 0.35, 1e-8);
    EXPECT_LT(fit->rms, 1e-8);
}

TEST(CircleFitTest, DegenerateInputIsIllConditioned)
{
    EXPECT_FALSE(fitCircle({{0, 0}, {1, 1}}).has_value());
    EXPECT_FALSE(fitCircle({{0, 0}, {1, 1}, {2, 2}, {3, 3}}).has_value());  // collinear
    EXPECT_FALSE(fitCircle({{0, 0}, {1, 0}, {std::nan(""), 2}}).has_value());
    EXPECT_FALSE(fitCircle({{1, 1}, {1, 1}, {1, 1}}).has_value());  // coincident
}

TEST(CircleFitTest, GeometricRefinementLimitsShortArcBias)
{
    // A laser sees at most half a trunk; with noise, the algebraic fit alone shrinks the
    // radius. Averaged over seeds, the refined radius must stay close to the truth.
    const double r = 0.3, noise = 0.01;
    double sum = 0;
    int n = 0;
    for (unsigned seed = 1; seed <= 50; ++seed)
    {
        const auto fit = fitCircle(arc({5, 0}, r, kPi - 1.0, kPi + 1.0, 12, noise, seed));
        ASSERT_TRUE(fit.has_value());
        sum += fit->radius;
        ++n;
        EXPECT_NEAR(fit->rms, noise, 0.01);
    }
    EXPECT_NEAR(sum / n, r, 0.02);
}

}  // namespace
