/**
 * @file sog_test.cpp
 * @brief SOG correlation derivatives against numeric differentiation, the covariance
 *        fit of thesis 5.4 on an exact Gaussian, and the SE(2) helpers.
 */
#include <gtest/gtest.h>
#include <hymm/scanslam/SogMatcher.h>
#include <hymm/scanslam/quadratic_fit.h>

#include <Eigen/LU>
#include <cmath>

#include "sim_scenes.h"

using namespace hymm::scanslam;
using namespace hymm::scanslam::testing;

TEST(PoseHelpersTest, ComposeInverseRoundTrip)
{
    const Vec3 a(1.5, -2, 2.9), b(0.3, 4, 1.0);
    const Vec3 ab = compose(a, b);
    const Vec3 back = compose(inverse(a), ab);
    EXPECT_LT(poseDifference(back, b).norm(), 1e-12);
    EXPECT_NEAR(ab.z(), 3.9 - 2 * M_PI, 1e-12);  // wrapped
    const Vec2 p(0.7, -0.2);
    EXPECT_LT((transformPoint(ab, p) - transformPoint(a, transformPoint(b, p))).norm(), 1e-12);
}

TEST(SogMatcherTest, GradientAndHessianMatchNumericDifferentiation)
{
    const auto world = threeObjects();
    const PointSet a = simulate(world, Vec3::Zero(), 11);
    const PointSet b = simulate(world, Vec3(0.2, 0.1, 0.02), 12);
    Segmenter::Options so;
    so.min_points = 10;
    const auto segs = Segmenter(so).segment(a);
    ASSERT_FALSE(segs.empty());
    const ScanTemplate tpl = ScanTemplate::fromSegment(a, segs.front());
    const SogMatcher m;
    const double cov_phi = 0.05;  // held fixed: derivatives are exact then
    for (double extra : {0.0, 0.04})
    {
        const Vec3 z = tpl.frame_in_sensor + Vec3(-0.15, -0.05, -0.01);
        const auto ev = m.evaluate(tpl.sog, b, z, extra, cov_phi, true);
        ASSERT_TRUE(std::isfinite(ev.log_l));
        const Vec3 hstep(1e-5, 1e-5, 1e-6);
        Vec3 gnum;
        Mat3 hnum;
        for (int k = 0; k < 3; ++k)
        {
            Vec3 d = Vec3::Zero();
            d(k) = hstep(k);
            const auto ep = m.evaluate(tpl.sog, b, z + d, extra, cov_phi, true);
            const auto em = m.evaluate(tpl.sog, b, z - d, extra, cov_phi, true);
            gnum(k) = (ep.log_l - em.log_l) / (2 * hstep(k));
            hnum.col(k) = (ep.gradient - em.gradient) / (2 * hstep(k));
        }
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(ev.gradient(k), gnum(k), 1e-4 * (1 + std::abs(gnum(k)))) << "k=" << k;
        EXPECT_LT((ev.hessian - hnum).norm(), 1e-3 * (1 + hnum.norm()));
    }
}

TEST(QuadraticFitTest, RecoversTheCovarianceOfAGaussianExactly)
{
    Mat3 p;
    p << 0.04, 0.01, 0.002, 0.01, 0.09, -0.003, 0.002, -0.003, 0.0009;
    const Mat3 inv = p.inverse();
    const Vec3 step(0.2, 0.3, 0.03);
    const auto offs = quadraticFitStencil(step);
    EXPECT_EQ(offs.size(), 18u);
    std::vector<double> c;
    for (const Vec3& d : offs) c.push_back(d.dot(inv * d));  // Eq. 5.16 for a Gaussian
    const auto fit = fitInverseCovariance(offs, c);
    ASSERT_TRUE(fit.has_value());
    EXPECT_LT((fit->inverse() - p).norm() / p.norm(), 1e-9);
    // Samples only along the axes cannot determine the cross terms.
    std::vector<Vec3> axes(offs.begin(), offs.begin() + 6);
    std::vector<double> ca(c.begin(), c.begin() + 6);
    EXPECT_FALSE(fitInverseCovariance(axes, ca).has_value());
    // A saddle is not a covariance.
    std::vector<double> neg = c;
    for (size_t i = 0; i < offs.size(); ++i) neg[i] = offs[i].x() * offs[i].x() - offs[i].y() * offs[i].y();
    EXPECT_FALSE(fitInverseCovariance(offs, neg).has_value());
}
