/**
 * @file sensor_models_test.cpp
 * @brief Eq. 4.15-4.16 against numeric differentiation, the occupancy model of Eq. 4.4
 *        at its analytic landmarks, and the (corrected) Bayes update of Eq. 4.11.
 */
#include "hymm/dense/RegionScan.h"
#include "hymm/dense/sensor_models.h"

#include <gtest/gtest.h>
#include <mrpt/math/num_jacobian.h>

#include <Eigen/LU>

#include <cmath>
#include <limits>

namespace
{
using namespace hymm::dense;

Eigen::MatrixXd numericJacobian(double r, double theta)
{
    Eigen::VectorXd x(2), inc(2);
    x << r, theta;
    inc << 1e-6, 1e-7;
    const std::function<void(const Eigen::VectorXd&, const int&, Eigen::VectorXd&)> f =
        [](const Eigen::VectorXd& z, const int&, Eigen::VectorXd& out) {
            out.resize(2);
            out << z[0] * std::cos(z[1]), z[0] * std::sin(z[1]);  // Eq. 4.15
        };
    Eigen::MatrixXd j;
    mrpt::math::estimateJacobian(x, f, inc, 0, j);
    return j;
}

TEST(SensorModelsTest, CartesianCovarianceEqualsNumericJacobianPropagation)
{
    const RangeBearingNoise noise{0.1, 1.0 * M_PI / 180};
    for (const double r : {0.5, 6.0, 24.0})
        for (const double th : {-2.9, -0.7, 0.0, 0.3, 1.9})
        {
            const Eigen::MatrixXd jn = numericJacobian(r, th);
            EXPECT_LT((polarToCartesianJacobian(r, th) - jn).norm(), 1e-6) << r << " " << th;
            Eigen::Matrix2d rr = Eigen::Matrix2d::Zero();
            rr(0, 0) = noise.range_std_m * noise.range_std_m;
            rr(1, 1) = noise.bearing_std_rad * noise.bearing_std_rad;
            const Eigen::Matrix2d expected = jn * rr * jn.transpose();
            const Eigen::Matrix2d p = polarToCartesianCovariance(r, th, noise);
            EXPECT_LT((p - expected).norm(), 1e-8 * (1 + expected.norm()));
            EXPECT_EQ(p(0, 1), p(1, 0));
            // Eigenvalues are sigma_r^2 (along the beam) and (r sigma_theta)^2 (across).
            const double along = Eigen::Vector2d(std::cos(th), std::sin(th)).dot(p * Eigen::Vector2d(std::cos(th), std::sin(th)));
            EXPECT_NEAR(along, rr(0, 0), 1e-12);
            EXPECT_NEAR(p.determinant(), rr(0, 0) * rr(1, 1) * r * r, 1e-12 * (1 + r * r));
        }
}

TEST(SensorModelsTest, OccupancyModelHitsItsAnalyticValues)
{
    const RangeBearingNoise n{0.1, 0.01};
    const OccupancyProfile pr{0.3, 0.9};
    const double z = 10, t = 0.2;
    EXPECT_NEAR(occupancyModel(z, t, z, t, true, n, pr), 0.9, 1e-12);  // peak: p_max
    // lambda_r = 0.5 at |dr| = sigma sqrt(2 ln 2) on both sides: the model is 0.5 there.
    const double half = n.range_std_m * std::sqrt(2 * std::log(2.0));
    EXPECT_NEAR(occupancyModel(z - half, t, z, t, true, n, pr), 0.5, 1e-9);
    EXPECT_NEAR(occupancyModel(z + half, t, z, t, true, n, pr), 0.5, 1e-9);
    // Deep in front on the beam axis: p_min; behind: unknown.
    EXPECT_NEAR(occupancyModel(5.0, t, z, t, true, n, pr), 0.3, 1e-9);
    EXPECT_NEAR(occupancyModel(11.0, t, z, t, true, n, pr), 0.5, 1e-12);
    // Off the beam's cone the free space fades back to unknown.
    EXPECT_GT(occupancyModel(5.0, t + 5 * n.bearing_std_rad, z, t, true, n, pr), 0.499);
    // A beam without return: free up to its end only.
    EXPECT_NEAR(occupancyModel(9.0, t, z, t, false, n, pr), 0.3, 1e-12);
    EXPECT_NEAR(occupancyModel(10.5, t, z, t, false, n, pr), 0.5, 1e-12);
    // Monotone rise through the peak from the free side.
    double prev = 0;
    for (double r = z - 0.4; r <= z; r += 0.01)
    {
        const double p = occupancyModel(r, t, z, t, true, n, pr);
        EXPECT_GE(p, prev - 1e-12);
        prev = p;
    }
}

TEST(SensorModelsTest, BayesUpdateIsTheCorrectedEquation411)
{
    EXPECT_NEAR(bayesOccupancyUpdate(0.5, 0.8), 0.8, 1e-15);  // Eq. 4.12: no prior information
    EXPECT_NEAR(bayesOccupancyUpdate(0.3, 0.7), 0.5, 1e-15);  // opposite odds cancel
    // Odds multiply: 0.6/0.4 * 0.9/0.1 = 13.5.
    EXPECT_NEAR(bayesOccupancyUpdate(0.6, 0.9), 13.5 / 14.5, 1e-15);
    EXPECT_NEAR(bayesOccupancyUpdate(0.9, 0.6), bayesOccupancyUpdate(0.6, 0.9), 1e-15);
}

TEST(SensorModelsTest, ScanNoiseOverridesAndRejectsBadValues)
{
    RegionScan s;
    const RangeBearingNoise fallback{0.1, 0.02};
    EXPECT_DOUBLE_EQ(effectiveNoise(s, fallback).range_std_m, 0.1);
    s.range_std_m = 0.05;
    EXPECT_DOUBLE_EQ(effectiveNoise(s, fallback).range_std_m, 0.05);
    EXPECT_DOUBLE_EQ(effectiveNoise(s, fallback).bearing_std_rad, 0.02);
    s.bearing_std_rad = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(effectiveNoise(s, fallback), std::invalid_argument);
    s.bearing_std_rad = -0.1;
    EXPECT_THROW(effectiveNoise(s, fallback), std::invalid_argument);
    EXPECT_THROW(validateNoise({0.0, 0.1}, "test"), std::invalid_argument);
}

}  // namespace
