/**
 * @file TriangleFrame_test.cpp
 * @brief Local coordinates (Eq. 3.9), their inverse and every App. C Jacobian
 *        against central finite differences.
 */
#include "hymm/ltr/TriangleFrame.h"

#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <stdexcept>

namespace
{
using hymm::ltr::FrameLimits;
using hymm::ltr::TriangleFrame;
using V2 = Eigen::Vector2d;

constexpr double kStep = 1e-6;
constexpr double kTol = 1e-6;

/** Central-difference Jacobian of f: R^2 -> R^2. */
Eigen::Matrix2d numericJacobian(const std::function<V2(const V2&)>& f, const V2& x0)
{
    Eigen::Matrix2d j;
    for (int c = 0; c < 2; ++c)
    {
        V2 xp = x0, xm = x0;
        xp(c) += kStep;
        xm(c) -= kStep;
        j.col(c) = (f(xp) - f(xm)) / (2 * kStep);
    }
    return j;
}

TriangleFrame::Vertices randomTriangle(std::mt19937& rng)
{
    std::uniform_real_distribution<double> u(-20, 20);
    for (;;)
    {
        TriangleFrame::Vertices v{V2(u(rng), u(rng)), V2(u(rng), u(rng)), V2(u(rng), u(rng))};
        if (TriangleFrame::tryCreate(v, FrameLimits{5.0, 50.0})) return v;
    }
}

TEST(TriangleFrameTest, LocalCoordinatesMatchThesisEquation39)
{
    const V2 l1(1, 2), l2(9, 3), l3(4, 8), x(5, 4);
    const TriangleFrame f(l1, l2, l3);
    const V2 d12 = l2 - l1, d13 = l3 - l1;
    const double den = d13.x() * d12.y() - d13.y() * d12.x();
    const double alpha = ((x.y() - l1.y()) * d13.x() - (x.x() - l1.x()) * d13.y()) / den;
    const double beta = ((x.x() - l1.x()) * d12.y() - (x.y() - l1.y()) * d12.x()) / den;
    EXPECT_NEAR(f.toLocal(x).x(), alpha, 1e-12);
    EXPECT_NEAR(f.toLocal(x).y(), beta, 1e-12);
    // Eq. 3.7: x = (1 - alpha - beta) L1 + alpha L2 + beta L3.
    EXPECT_TRUE(((1 - alpha - beta) * l1 + alpha * l2 + beta * l3).isApprox(x, 1e-12));
}

TEST(TriangleFrameTest, LocalGlobalRoundTrip)
{
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-30, 30);
    for (int t = 0; t < 200; ++t)
    {
        const TriangleFrame f(randomTriangle(rng));
        const V2 x(u(rng), u(rng));
        EXPECT_LT((f.toGlobal(f.toLocal(x)) - x).norm(), 1e-9);
        const V2 l(u(rng) / 10, u(rng) / 10);
        EXPECT_LT((f.toLocal(f.toGlobal(l)) - l).norm(), 1e-9);
    }
    const TriangleFrame f(V2(0, 0), V2(4, 0), V2(0, 4));
    EXPECT_TRUE(f.toLocal(f.vertex(1)).isApprox(V2(1, 0)));
    EXPECT_TRUE(f.toLocal(f.vertex(2)).isApprox(V2(0, 1)));
    EXPECT_TRUE(f.contains(V2(1, 1)));
    EXPECT_FALSE(f.contains(V2(3, 3)));
}

TEST(TriangleFrameTest, LocalJacobiansMatchNumericDifferentiation)
{
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(-30, 30);
    for (int t = 0; t < 50; ++t)
    {
        const TriangleFrame::Vertices v = randomTriangle(rng);
        const TriangleFrame f(v);
        const V2 x(u(rng), u(rng));
        const Eigen::Matrix2d jx =
            numericJacobian([&](const V2& p) { return f.toLocal(p); }, x);
        EXPECT_LT((f.jacLocalWrtPoint() - jx).cwiseAbs().maxCoeff(), kTol);
        const Eigen::Matrix<double, 2, 6> jall = f.jacLocalWrtVertices(x);
        for (int k = 0; k < 3; ++k)
        {
            const Eigen::Matrix2d jn = numericJacobian(
                [&](const V2& lk) {
                    TriangleFrame::Vertices w = v;
                    w[static_cast<size_t>(k)] = lk;
                    return TriangleFrame(w).toLocal(x);
                },
                v[static_cast<size_t>(k)]);
            EXPECT_LT((f.jacLocalWrtVertex(x, k) - jn).cwiseAbs().maxCoeff(), kTol)
                << "vertex " << k;
            EXPECT_LT((jall.block<2, 2>(0, 2 * k) - jn).cwiseAbs().maxCoeff(), kTol);
        }
    }
}

TEST(TriangleFrameTest, GlobalJacobiansMatchNumericDifferentiation)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-2, 2);
    for (int t = 0; t < 50; ++t)
    {
        const TriangleFrame::Vertices v = randomTriangle(rng);
        const TriangleFrame f(v);
        const V2 l(u(rng), u(rng));
        const Eigen::Matrix2d jl = numericJacobian([&](const V2& q) { return f.toGlobal(q); }, l);
        EXPECT_LT((f.jacGlobalWrtLocal() - jl).cwiseAbs().maxCoeff(), kTol);
        const Eigen::Matrix<double, 2, 6> jall = TriangleFrame::jacGlobalWrtVertices(l);
        for (int k = 0; k < 3; ++k)
        {
            const Eigen::Matrix2d jn = numericJacobian(
                [&](const V2& lk) {
                    TriangleFrame::Vertices w = v;
                    w[static_cast<size_t>(k)] = lk;
                    return TriangleFrame(w).toGlobal(l);
                },
                v[static_cast<size_t>(k)]);
            EXPECT_LT((TriangleFrame::jacGlobalWrtVertex(l, k) - jn).cwiseAbs().maxCoeff(), kTol);
            EXPECT_LT((jall.block<2, 2>(0, 2 * k) - jn).cwiseAbs().maxCoeff(), kTol);
        }
    }
}

// The printed Eq. C.14 reads d alpha / d d13 = [dx, -dy] / Delta; the derivative
// of the numerator of Eq. C.3 is [dy, -dx]. This documents the transcription error
// and that the chain-rule form C.7 with the corrected term equals our jacobian.
TEST(TriangleFrameTest, ChainRuleOfAppendixCWithCorrectedC14)
{
    const V2 l1(1, 2), l2(9, 3), l3(4, 8), x(5, 4);
    const TriangleFrame f(l1, l2, l3);
    const V2 d = x - l1, d12 = l2 - l1, d13 = l3 - l1, d23 = l3 - l2;
    const double delta = d13.x() * d12.y() - d13.y() * d12.x();  // C.6
    const double alpha = f.toLocal(x).x(), beta = f.toLocal(x).y();
    const Eigen::RowVector2d da_ddx = Eigen::RowVector2d(-d13.y(), d13.x()) / delta;  // C.11
    const Eigen::RowVector2d db_ddx = Eigen::RowVector2d(d12.y(), -d12.x()) / delta;  // C.12
    const Eigen::RowVector2d da_dd13 = Eigen::RowVector2d(d.y(), -d.x()) / delta;  // C.14 fixed
    const Eigen::RowVector2d db_dd12 = Eigen::RowVector2d(-d.y(), d.x()) / delta;  // C.15
    const Eigen::RowVector2d dD_dL1(d23.y(), -d23.x());                           // C.20
    const Eigen::RowVector2d dD_dL2(-d13.y(), d13.x());                           // C.21
    const Eigen::RowVector2d dD_dL3(d12.y(), -d12.x());                           // C.22
    const Eigen::RowVector2d da_dL1 = -da_ddx - da_dd13 - alpha / delta * dD_dL1;  // C.7
    const Eigen::RowVector2d db_dL1 = -db_ddx - db_dd12 - beta / delta * dD_dL1;
    const Eigen::RowVector2d da_dL2 = -alpha / delta * dD_dL2;  // C.8
    const Eigen::RowVector2d db_dL2 = db_dd12 - beta / delta * dD_dL2;
    const Eigen::RowVector2d da_dL3 = da_dd13 - alpha / delta * dD_dL3;  // C.9
    const Eigen::RowVector2d db_dL3 = -beta / delta * dD_dL3;
    EXPECT_LT((f.jacLocalWrtVertex(x, 0).row(0) - da_dL1).norm(), 1e-12);
    EXPECT_LT((f.jacLocalWrtVertex(x, 0).row(1) - db_dL1).norm(), 1e-12);
    EXPECT_LT((f.jacLocalWrtVertex(x, 1).row(0) - da_dL2).norm(), 1e-12);
    EXPECT_LT((f.jacLocalWrtVertex(x, 1).row(1) - db_dL2).norm(), 1e-12);
    EXPECT_LT((f.jacLocalWrtVertex(x, 2).row(0) - da_dL3).norm(), 1e-12);
    EXPECT_LT((f.jacLocalWrtVertex(x, 2).row(1) - db_dL3).norm(), 1e-12);
    // The transcribed C.14 gives a different (wrong) derivative here.
    const Eigen::RowVector2d printed_c14 = Eigen::RowVector2d(d.x(), -d.y()) / delta;
    EXPECT_GT(((printed_c14 - alpha / delta * dD_dL3) - da_dL3).norm(), 1e-3);
    EXPECT_LT((f.jacLocalWrtPoint().row(0) - da_ddx).norm(), 1e-12);  // C.5
}

TEST(TriangleFrameTest, DegenerateTrianglesAreRefusedWithoutNaN)
{
    const V2 a(0, 0), b(10, 0);
    // Collinear: zero area.
    EXPECT_THROW(TriangleFrame(a, b, V2(5, 0)), std::invalid_argument);
    std::string why;
    EXPECT_FALSE(TriangleFrame::tryCreate({a, b, V2(5, 0)}, FrameLimits(), &why));
    EXPECT_NE(why.find("area"), std::string::npos) << why;
    // Coincident vertices.
    EXPECT_FALSE(TriangleFrame::tryCreate({a, a, b}));
    // A sliver with a fine area but an enormous condition number.
    const FrameLimits lim{1e-3, 100.0};
    why.clear();
    EXPECT_FALSE(TriangleFrame::tryCreate({a, V2(1000, 0), V2(1000, 0.01)}, lim, &why));
    EXPECT_NE(why.find("condition"), std::string::npos) << why;
    // Not finite.
    EXPECT_FALSE(TriangleFrame::tryCreate({a, b, V2(std::nan(""), 1)}));
    // A well-shaped triangle passes and gives finite output.
    const auto ok = TriangleFrame::tryCreate({a, b, V2(0, 10)}, lim);
    ASSERT_TRUE(ok);
    EXPECT_TRUE(ok->toLocal(V2(3, 3)).allFinite());
    EXPECT_THROW(ok->jacLocalWrtVertex(V2(1, 1), 3), std::out_of_range);
}

}  // namespace
