#include <gtest/gtest.h>
#include <hymm/core/UteVehicleModel.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <functional>
#include <random>

namespace
{
using hymm::core::UteParams;

// Central differences of f around x (Jacobian columns).
template <int N, int M>
Eigen::Matrix<double, N, M> numericJacobian(
    const std::function<Eigen::Matrix<double, N, 1>(const Eigen::Matrix<double, M, 1>&)>& f,
    const Eigen::Matrix<double, M, 1>& x, double h = 1e-6)
{
    Eigen::Matrix<double, N, M> J;
    for (int j = 0; j < M; ++j)
    {
        auto xp = x, xm = x;
        xp[j] += h;
        xm[j] -= h;
        Eigen::Matrix<double, N, 1> d = f(xp) - f(xm);
        if (N == 3) d[N - 1] = mrpt::math::wrapToPi(d[N - 1]);
        J.col(j) = d / (2 * h);
    }
    return J;
}

TEST(UteVehicleModelTest, StraightLineMovesAlongHeading)
{
    UteParams p;
    const Eigen::Vector3d x0(1.0, 2.0, M_PI / 3);
    const auto x1 = hymm::core::uteStep(x0, Eigen::Vector2d(2.0, 0.0), 0.5, p);
    EXPECT_NEAR(x1[0], 1.0 + 1.0 * std::cos(M_PI / 3), 1e-12);
    EXPECT_NEAR(x1[1], 2.0 + 1.0 * std::sin(M_PI / 3), 1e-12);
    EXPECT_NEAR(x1[2], M_PI / 3, 1e-12);
}

TEST(UteVehicleModelTest, StepMatchesEquationA4)
{
    UteParams p;  // L = 2.83, H = 0.76, a = 3.78, b = 0.5
    const Eigen::Vector3d x(3.0, -4.0, 0.7);
    const double ve = 3.0, alpha = 0.2, dt = 0.025;
    const double vc = ve / (1 - std::tan(alpha) * p.H / p.L);  // Eq. A.3
    const double phi = x[2];
    const double ex = x[0] + dt * (vc * std::cos(phi) - vc / p.L * std::tan(alpha) *
                                                           (p.a * std::sin(phi) + p.b * std::cos(phi)));
    const double ey = x[1] + dt * (vc * std::sin(phi) + vc / p.L * std::tan(alpha) *
                                                           (p.a * std::cos(phi) - p.b * std::sin(phi)));
    const double ephi = phi + dt * vc / p.L * std::tan(alpha);
    const auto xn = hymm::core::uteStep(x, Eigen::Vector2d(ve, alpha), dt, p);
    EXPECT_NEAR(xn[0], ex, 1e-12);
    EXPECT_NEAR(xn[1], ey, 1e-12);
    EXPECT_NEAR(xn[2], ephi, 1e-12);
}

TEST(UteVehicleModelTest, JacobiansMatchNumericDifferentiation)
{
    UteParams p;
    for (double phi : {-3.0, -1.2, 0.0, 0.9, 2.8})
    {
        const Eigen::Vector3d x(10.0, 5.0, phi);
        const Eigen::Vector2d u(3.1, -0.3);
        const double dt = 0.1;
        Eigen::Matrix3d F;
        Eigen::Matrix<double, 3, 2> B;
        hymm::core::uteStep(x, u, dt, p, &F, &B);
        const auto Fn = numericJacobian<3, 3>(
            [&](const Eigen::Vector3d& xx) { return hymm::core::uteStep(xx, u, dt, p); }, x);
        const auto Bn = numericJacobian<3, 2>(
            [&](const Eigen::Vector2d& uu) { return hymm::core::uteStep(x, uu, dt, p); }, u);
        EXPECT_LT((F - Fn).cwiseAbs().maxCoeff(), 1e-6) << "phi=" << phi;
        EXPECT_LT((B - Bn).cwiseAbs().maxCoeff(), 1e-6) << "phi=" << phi;
    }
}

TEST(UteVehicleModelTest, IncrementComposesToStep)
{
    UteParams p;
    const Eigen::Vector3d x(-2.0, 7.0, 2.5);
    const Eigen::Vector2d u(4.0, 0.25);
    const double dt = 0.2;
    Eigen::Matrix<double, 3, 2> J;
    const auto d = hymm::core::uteIncrement(u, dt, p, &J);
    const auto xn = hymm::core::uteStep(x, u, dt, p);
    const double c = std::cos(x[2]), s = std::sin(x[2]);
    EXPECT_NEAR(x[0] + c * d[0] - s * d[1], xn[0], 1e-12);
    EXPECT_NEAR(x[1] + s * d[0] + c * d[1], xn[1], 1e-12);
    EXPECT_NEAR(mrpt::math::wrapToPi(x[2] + d[2] - xn[2]), 0.0, 1e-12);
    const auto Jn = numericJacobian<3, 2>(
        [&](const Eigen::Vector2d& uu) { return hymm::core::uteIncrement(uu, dt, p); }, u);
    EXPECT_LT((J - Jn).cwiseAbs().maxCoeff(), 1e-6);
}

// 1/2 sum_ij Q_ij d2d/du_i du_j by central second differences.
Eigen::Vector3d numericNoiseBias(const Eigen::Vector2d& u, double dt, const UteParams& p,
                                 const Eigen::Matrix2d& Q, double h = 1e-4)
{
    const auto d = [&](double dv, double da)
    { return hymm::core::uteIncrement(u + Eigen::Vector2d(dv, da), dt, p); };
    const Eigen::Vector3d d_vv = (d(h, 0) - 2 * d(0, 0) + d(-h, 0)) / (h * h);
    const Eigen::Vector3d d_aa = (d(0, h) - 2 * d(0, 0) + d(0, -h)) / (h * h);
    const Eigen::Vector3d d_va = (d(h, h) - d(h, -h) - d(-h, h) + d(-h, -h)) / (4 * h * h);
    return 0.5 * (Q(0, 0) * d_vv + Q(1, 1) * d_aa + (Q(0, 1) + Q(1, 0)) * d_va);
}

TEST(UteVehicleModelTest, NoiseBiasMatchesNumericSecondDerivatives)
{
    UteParams p;
    Eigen::Matrix2d Q;
    Q << 0.25, 0.004, 0.004, std::pow(5.0 * M_PI / 180, 2);
    for (const Eigen::Vector2d& u : {Eigen::Vector2d(3.0, 0.0), Eigen::Vector2d(3.0, 0.19),
                                    Eigen::Vector2d(1.5, -0.4), Eigen::Vector2d(-2.0, 0.3)})
    {
        const Eigen::Vector3d b = hymm::core::uteIncrementNoiseBias(u, 0.025, p, Q);
        const Eigen::Vector3d bn = numericNoiseBias(u, 0.025, p, Q);
        EXPECT_LT((b - bn).cwiseAbs().maxCoeff(), 1e-7 + 1e-4 * bn.cwiseAbs().maxCoeff())
            << "u = " << u.transpose() << ": " << b.transpose() << " vs " << bn.transpose();
    }
    // Straight line, independent readings: the heading rate bias is v H std_alpha^2 / L^2.
    const Eigen::Matrix2d Qd = Q.diagonal().asDiagonal();
    const auto b0 = hymm::core::uteIncrementNoiseBias(Eigen::Vector2d(3.0, 0.0), 1.0, p, Qd);
    EXPECT_NEAR(b0[2], 3.0 * p.H * Q(1, 1) / (p.L * p.L), 1e-12);
}

TEST(UteVehicleModelTest, NoiseBiasIsTheMeanOffsetOfNoisyReadings)
{
    // The mean of the increments of noisy readings is off the noise-free increment by the
    // bias (to second order): Monte Carlo with 400k draws, within 4 standard errors.
    UteParams p;
    const double sv = 0.5, sa = 5.0 * M_PI / 180, dt = 0.025;
    const Eigen::Matrix2d Q = Eigen::Vector2d(sv * sv, sa * sa).asDiagonal();
    std::mt19937 rng(7);
    std::normal_distribution<double> n01;
    for (const Eigen::Vector2d& u : {Eigen::Vector2d(3.0, 0.0), Eigen::Vector2d(3.0, 0.19)})
    {
        const int n = 400000;
        Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sq = Eigen::Vector3d::Zero();
        const Eigen::Vector3d d0 = hymm::core::uteIncrement(u, dt, p);
        for (int i = 0; i < n; ++i)
        {
            const Eigen::Vector2d un = u + Eigen::Vector2d(sv * n01(rng), sa * n01(rng));
            const Eigen::Vector3d e = hymm::core::uteIncrement(un, dt, p) - d0;
            sum += e;
            sq += e.cwiseProduct(e);
        }
        const Eigen::Vector3d mean = sum / n;
        const Eigen::Vector3d se = ((sq / n - mean.cwiseProduct(mean)) / n).cwiseSqrt();
        const Eigen::Vector3d b = hymm::core::uteIncrementNoiseBias(u, dt, p, Q);
        for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(mean[i] - b[i]), 4 * se[i]) << i;
        // The heading bias is many standard errors from zero: the test can tell it apart.
        EXPECT_GT(std::abs(mean[2]), 8 * se[2]);
    }
}

TEST(UteVehicleModelTest, ExtremeSteeringIsRejected)
{
    UteParams p;
    p.H = 2.0;
    EXPECT_THROW(hymm::core::uteStep(Eigen::Vector3d::Zero(), Eigen::Vector2d(1.0, 1.2), 0.1, p),
                 std::invalid_argument);
}

}  // namespace
