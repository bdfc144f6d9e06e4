#include <gtest/gtest.h>
#include <hymm/core/RangeBearingModel.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>

namespace
{
using namespace hymm::core;

template <typename F, int M>
Eigen::Matrix<double, 2, M> numJac(F f, const Eigen::Matrix<double, M, 1>& x, bool wrap_second)
{
    const double h = 1e-6;
    Eigen::Matrix<double, 2, M> J;
    for (int j = 0; j < M; ++j)
    {
        auto xp = x, xm = x;
        xp[j] += h;
        xm[j] -= h;
        Eigen::Vector2d d = f(xp) - f(xm);
        if (wrap_second) d[1] = mrpt::math::wrapToPi(d[1]);
        J.col(j) = d / (2 * h);
    }
    return J;
}

TEST(RangeBearingModelTest, ObservesKnownGeometry)
{
    // Vehicle at origin facing +y, sensor 1 m ahead: a landmark at (0, 5) is 4 m away, dead ahead.
    const Vec2 z = observeRangeBearing(Vec3(0, 0, M_PI / 2), Vec3(1, 0, 0), Vec2(0, 5));
    EXPECT_NEAR(z[0], 4.0, 1e-12);
    EXPECT_NEAR(z[1], 0.0, 1e-12);
}

TEST(RangeBearingModelTest, InverseUndoesObservation)
{
    const Vec3 v(3, -2, 2.9), s(0.5, -0.2, 0.3);
    const Vec2 lm(-7, 4);
    const Vec2 z = observeRangeBearing(v, s, lm);
    const Vec2 back = inverseRangeBearing(v, s, z);
    EXPECT_LT((back - lm).norm(), 1e-10);
}

TEST(RangeBearingModelTest, JacobiansMatchNumericDifferentiation)
{
    for (double phi : {-3.1, -0.5, 0.0, 1.4, 3.1})
    {
        const Vec3 v(1.5, -2.0, phi), s(3.78, 0.5, 0.05);
        const Vec2 lm(12.0, 9.0);
        Mat23 Hv;
        Mat2 Hl;
        const Vec2 z = observeRangeBearing(v, s, lm, &Hv, &Hl);
        auto fv = [&](const Vec3& x) { return observeRangeBearing(x, s, lm); };
        auto fl = [&](const Vec2& x) { return observeRangeBearing(v, s, x); };
        EXPECT_LT((Hv - numJac<decltype(fv), 3>(fv, v, true)).cwiseAbs().maxCoeff(), 1e-6);
        EXPECT_LT((Hl - numJac<decltype(fl), 2>(fl, lm, true)).cwiseAbs().maxCoeff(), 1e-6);

        Mat23 Gv;
        Mat2 Gz;
        inverseRangeBearing(v, s, z, &Gv, &Gz);
        auto gv = [&](const Vec3& x) { return inverseRangeBearing(x, s, z); };
        auto gz = [&](const Vec2& x) { return inverseRangeBearing(v, s, x); };
        EXPECT_LT((Gv - numJac<decltype(gv), 3>(gv, v, false)).cwiseAbs().maxCoeff(), 1e-6);
        EXPECT_LT((Gz - numJac<decltype(gz), 2>(gz, z, false)).cwiseAbs().maxCoeff(), 1e-6);
    }
}

TEST(RangeBearingModelTest, LandmarkAtSensorIsAnError)
{
    EXPECT_THROW(observeRangeBearing(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec2(1, 0)), std::domain_error);
}

}  // namespace
