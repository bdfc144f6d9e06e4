#include <gtest/gtest.h>
#include <hymm/datasets/ImportSummary.h>
#include <hymm/datasets/OdometryIntegrator.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Eigenvalues>
#include <cmath>

namespace
{
using hymm::datasets::OdometryIntegrator;
using Model = OdometryIntegrator::Model;
using Sample = OdometryIntegrator::ControlSample;

std::vector<Sample> constantControls(double u0, double u1, double dt, double T)
{
    std::vector<Sample> s;
    const auto n = static_cast<int>(std::lround(T / dt));
    for (int i = 0; i <= n; ++i) s.push_back({i * dt, u0, u1});
    return s;
}

TEST(OdometryIntegratorTest, ConstantSpeedAndSteeringFollowsTheAnalyticCircle)
{
    const hymm::core::UteParams p{2.83, 0.76, 3.78, 0.5};
    const double v = 2.0, alpha = 0.2, T = 10.0;
    const OdometryIntegrator odo(Model::Ute, p, {}, constantControls(v, alpha, 1e-3, T));
    const auto inc = odo.integrate(0.0, T);

    // Rigid rotation of the vehicle about the instantaneous centre of rotation, which lies
    // on the rear axle at R = L / tan(alpha); in the tracked point's frame: (-a, R - b).
    const double vc = v / (1.0 - std::tan(alpha) * p.H / p.L);  // Eq. A.3
    const double w = vc * std::tan(alpha) / p.L;
    const double th = w * T;
    const Eigen::Vector2d icr(-p.a, p.L / std::tan(alpha) - p.b);
    const Eigen::Vector2d expected = icr + Eigen::Rotation2Dd(th) * (-icr);

    EXPECT_NEAR(inc.mean.x(), expected.x(), 0.02);
    EXPECT_NEAR(inc.mean.y(), expected.y(), 0.02);
    EXPECT_NEAR(inc.mean.phi(), mrpt::math::wrapToPi(th), 1e-9);
    EXPECT_NEAR((Eigen::Vector2d(inc.mean.x(), inc.mean.y()) - icr).norm(), icr.norm(), 0.01);
    EXPECT_EQ(inc.uncovered_s, 0.0);
}

TEST(OdometryIntegratorTest, UnicycleConstantTwistFollowsTheArc)
{
    const double v = 1.0, w = 0.5, T = 4.0;
    const OdometryIntegrator odo(Model::Unicycle, {}, {}, constantControls(v, w, 0.02, T));
    const auto inc = odo.integrate(0.0, T);
    EXPECT_NEAR(inc.mean.x(), v / w * std::sin(w * T), 1e-4);
    EXPECT_NEAR(inc.mean.y(), v / w * (1 - std::cos(w * T)), 1e-4);
    EXPECT_NEAR(inc.mean.phi(), w * T, 1e-9);
}

TEST(OdometryIntegratorTest, SplittingTheIntervalComposesToTheWhole)
{
    const hymm::core::UteParams p;
    std::vector<Sample> s;
    for (int i = 0; i < 200; ++i) s.push_back({0.025 * i, 1.0 + 0.01 * i, 0.3 * std::sin(0.05 * i)});
    const OdometryIntegrator odo(Model::Ute, p, {}, s);
    const auto whole = odo.integrate(0.1, 4.0);
    // Cut on a sample boundary: the same Euler steps, so the same result.
    const auto on = odo.integrate(0.1, 1.25).mean + odo.integrate(1.25, 4.0).mean;
    EXPECT_NEAR(on.x(), whole.mean.x(), 1e-9);
    EXPECT_NEAR(on.y(), whole.mean.y(), 1e-9);
    EXPECT_NEAR(on.phi(), whole.mean.phi(), 1e-9);
    // Cut inside a sample: that one Euler step becomes two, a second-order change.
    const auto in = odo.integrate(0.1, 1.2345).mean + odo.integrate(1.2345, 4.0).mean;
    EXPECT_NEAR(in.x(), whole.mean.x(), 1e-4);
    EXPECT_NEAR(in.y(), whole.mean.y(), 1e-4);
    EXPECT_NEAR(in.phi(), whole.mean.phi(), 1e-9);
}

TEST(OdometryIntegratorTest, SpeedNoiseAddsUpAlongAStraightLine)
{
    OdometryIntegrator::Options o;
    o.std_speed_mps = 0.2;
    o.std_steering_deg = 0.0;
    o.min_std_xy_m = 1e-4;
    const double dt = 0.025;
    const int n = 40;
    const OdometryIntegrator odo(Model::Ute, {}, o, constantControls(3.0, 0.0, dt, n * dt));
    const auto inc = odo.integrate(0.0, n * dt);
    // n independent steps of std (0.2 dt) in x; nothing in y or phi but the floor.
    EXPECT_NEAR(inc.cov(0, 0), n * std::pow(0.2 * dt, 2) + 1e-8, 1e-12);
    EXPECT_NEAR(inc.cov(1, 1), 1e-8, 1e-12);
    EXPECT_NEAR(inc.mean.x(), 3.0 * n * dt, 1e-9);
}

TEST(OdometryIntegratorTest, CovarianceIsPositiveDefiniteStandingStillAndWhileTurning)
{
    const hymm::core::UteParams p;
    const OdometryIntegrator still(Model::Ute, p, {}, constantControls(0.0, 0.0, 0.025, 2.0));
    const OdometryIntegrator turning(Model::Ute, p, {}, constantControls(4.0, 0.3, 0.025, 20.0));
    for (const auto& inc : {still.integrate(0, 2.0), turning.integrate(0, 20.0)})
    {
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(inc.cov);
        EXPECT_GT(es.eigenvalues().minCoeff(), 0.0);
        EXPECT_TRUE(inc.cov.isApprox(inc.cov.transpose()));
    }
    EXPECT_GT(turning.integrate(0, 20.0).cov.trace(), turning.integrate(0, 2.0).cov.trace());
}

TEST(OdometryIntegratorTest, HoldIsLimitedAndGapsAreReported)
{
    OdometryIntegrator::Options o;
    o.max_hold_s = 0.5;
    const OdometryIntegrator odo(Model::Unicycle, {}, o, {{1.0, 2.0, 0.0}, {11.0, 2.0, 0.0}});
    const auto inc = odo.integrate(0.0, 12.0);
    EXPECT_NEAR(inc.mean.x(), 2.0 * 0.5 * 2, 1e-9);  // two samples, each held 0.5 s
    EXPECT_NEAR(inc.uncovered_s, 1.0 + 9.5 + 0.5, 1e-9);
    EXPECT_THROW(odo.integrate(2.0, 1.0), std::invalid_argument);
}

TEST(OdometryIntegratorTest, SanitizeDropsAndCountsBadSamples)
{
    hymm::datasets::ImportSummary sum;
    const std::vector<Sample> raw = {{0.0, 1, 0},    {0.025, NAN, 0}, {0.05, 1, 0},
                                     {0.05, 1, 0},   {0.04, 1, 0},    {0.075, 1, 1.5},
                                     {0.1, 1, -0.1}};
    const auto ok = OdometryIntegrator::sanitize(raw, Model::Ute, {}, sum);
    ASSERT_EQ(ok.size(), 3u);
    EXPECT_EQ(ok[2].t, 0.1);
    EXPECT_EQ(sum.skippedCount("odometry_nan"), 1u);
    EXPECT_EQ(sum.skippedCount("odometry_non_monotonic"), 2u);
    EXPECT_EQ(sum.skippedCount("odometry_steering_out_of_range"), 1u);
    // The constructor refuses what sanitize would have dropped.
    EXPECT_THROW(OdometryIntegrator(Model::Ute, {}, {}, raw), std::invalid_argument);
}

}  // namespace
