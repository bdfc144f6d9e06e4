#include "test_helpers.h"

#include <gtest/gtest.h>
#include <hymm/ekf/pose_composition.h>
#include <mrpt/poses/CPose2D.h>

namespace
{
using hymm::ekf::composePose;
using hymm::ekf::testing::numericJacobian;

TEST(PoseCompositionTest, MatchesMrptPoseComposition)
{
    const Eigen::Vector3d x(1.0, -2.0, 2.8), d(0.7, 0.3, 0.9);
    const mrpt::poses::CPose2D c =
        mrpt::poses::CPose2D(x[0], x[1], x[2]) + mrpt::poses::CPose2D(d[0], d[1], d[2]);
    const Eigen::Vector3d r = composePose(x, d);
    EXPECT_NEAR(r[0], c.x(), 1e-12);
    EXPECT_NEAR(r[1], c.y(), 1e-12);
    EXPECT_NEAR(r[2], c.phi(), 1e-12);  // both wrapped to (-pi, pi]
}

TEST(PoseCompositionTest, JacobiansMatchNumericDifferentiation)
{
    for (double phi : {-3.1, -1.0, 0.0, 0.4, 3.1})
    {
        const Eigen::Vector3d x(2.0, 1.0, phi), d(0.8, -0.25, 0.3);
        Eigen::Matrix3d Jx, Jd;
        composePose(x, d, &Jx, &Jd);
        const Eigen::MatrixXd nx = numericJacobian(
            [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return composePose(v, d); }, x, {2});
        const Eigen::MatrixXd nd = numericJacobian(
            [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return composePose(x, v); }, d, {2});
        EXPECT_LT((Jx - nx).cwiseAbs().maxCoeff(), 1e-6) << "phi=" << phi;
        EXPECT_LT((Jd - nd).cwiseAbs().maxCoeff(), 1e-6) << "phi=" << phi;
    }
}

}  // namespace
