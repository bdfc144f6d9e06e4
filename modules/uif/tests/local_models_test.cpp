/**
 * @file local_models_test.cpp
 * @brief Eq. 3.27-3.29 Jacobians against central differences, and the chain rule that
 *        ties the thesis' local-pose route (Eq. 3.29-3.30) to the store's global one.
 */
#include <hymm/uif/local_models.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

namespace
{
using hymm::ltr::TriangleFrame;
using namespace hymm::uif;

Eigen::MatrixXd numericJacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
    int angle_row = -1, double h = 1e-6)
{
    const Eigen::VectorXd f0 = f(x);
    Eigen::MatrixXd J(f0.size(), x.size());
    for (Eigen::Index j = 0; j < x.size(); ++j)
    {
        Eigen::VectorXd xp = x, xm = x;
        xp[j] += h;
        xm[j] -= h;
        Eigen::VectorXd d = f(xp) - f(xm);
        if (angle_row >= 0) d[angle_row] = std::remainder(d[angle_row], 2.0 * M_PI);
        J.col(j) = d / (2 * h);
    }
    return J;
}

TriangleFrame frameOf(const Eigen::VectorXd& v6)
{
    return TriangleFrame(v6.segment<2>(0), v6.segment<2>(2), v6.segment<2>(4));
}

struct Case
{
    Eigen::Vector3d pose, sensor;
    Eigen::Vector2d z;
    Eigen::Matrix<double, 6, 1> v;  // sheared triangle: D is not a similarity
};

std::vector<Case> cases()
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Case> out;
    for (int i = 0; i < 20; ++i)
    {
        Case c;
        c.pose << 3 * u(rng), 2 * u(rng), M_PI * u(rng);
        c.sensor << 0.5 * u(rng), 0.2 * u(rng), 0.3 * u(rng);
        c.z << 4.0 + 3 * u(rng), 1.5 * u(rng);
        // Axis a points anywhere, including the left half-plane where atan loses the quadrant.
        const double th = M_PI * u(rng);
        c.v << u(rng), u(rng), 0, 0, 0, 0;
        c.v.segment<2>(2) = c.v.head<2>() + 9.0 * Eigen::Vector2d(std::cos(th), std::sin(th));
        c.v.segment<2>(4) = c.v.head<2>() + 7.0 * Eigen::Vector2d(std::cos(th + 1.2), std::sin(th + 1.2)) +
                            Eigen::Vector2d(u(rng), u(rng));
        out.push_back(c);
    }
    return out;
}

TEST(LocalModelsTest, LocalVehiclePoseJacobiansMatchNumeric)
{
    for (const Case& c : cases())
    {
        const TriangleFrame f = frameOf(c.v);
        Mat3 Jp;
        Mat36 Jv;
        const Vec3 lp = localVehiclePose(c.pose, f, &Jp, &Jv);
        const auto byPose = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd
        { return localVehiclePose(x, f); };
        const auto byVertices = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd
        { return localVehiclePose(c.pose, frameOf(x)); };
        EXPECT_LT((Jp - numericJacobian(byPose, c.pose, 2)).cwiseAbs().maxCoeff(), 1e-6);
        EXPECT_LT((Jv - numericJacobian(byVertices, c.v, 2)).cwiseAbs().maxCoeff(), 1e-6);
        // Eq. 3.28 with atan2: the round trip recovers the heading in every quadrant.
        EXPECT_LT((globalVehiclePose(lp, f).head<2>() - c.pose.head<2>()).norm(), 1e-9);
        EXPECT_NEAR(std::remainder(globalVehiclePose(lp, f).z() - c.pose.z(), 2 * M_PI), 0.0, 1e-12);
    }
}

TEST(LocalModelsTest, TranscribedEq328LosesTheQuadrantOfTheAxis)
{
    // Axis pointing to -x: atan(dy/dx) differs from the axis heading by pi.
    const TriangleFrame f(Eigen::Vector2d(0, 0), Eigen::Vector2d(-10, 1), Eigen::Vector2d(-3, -8));
    const Vec3 pose(-4, -2, 0.3);
    const double gamma_atan = pose.z() - std::atan(1.0 / -10.0);
    const double gamma = localVehiclePose(pose, f).z();
    EXPECT_NEAR(std::abs(std::remainder(gamma - gamma_atan, 2 * M_PI)), M_PI, 1e-12);
    EXPECT_NEAR(std::remainder(globalVehiclePose(localVehiclePose(pose, f), f).z() - pose.z(), 2 * M_PI), 0, 1e-12);
}

TEST(LocalModelsTest, PointLocalJacobiansMatchNumeric)
{
    for (const Case& c : cases())
    {
        const TriangleFrame f = frameOf(c.v);
        PointLocalJacobians J;
        pointLocal(c.pose, c.sensor, c.z, f, &J);
        const auto byPose = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd
        { return pointLocal(x, c.sensor, c.z, f); };
        const auto byZ = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd
        { return pointLocal(c.pose, c.sensor, x, f); };
        const auto byVertices = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd
        { return pointLocal(c.pose, c.sensor, c.z, frameOf(x)); };
        EXPECT_LT((J.pose - numericJacobian(byPose, c.pose)).cwiseAbs().maxCoeff(), 1e-6);
        EXPECT_LT((J.z - numericJacobian(byZ, c.z)).cwiseAbs().maxCoeff(), 1e-6);
        EXPECT_LT((J.vertices - numericJacobian(byVertices, c.v)).cwiseAbs().maxCoeff(), 1e-6);
    }
}

TEST(LocalModelsTest, Eq329JacobiansMatchNumericAndChainToTheGlobalRoute)
{
    for (const Case& c : cases())
    {
        const TriangleFrame f = frameOf(c.v);
        Mat3 Jp;
        Mat36 Jv;
        const Vec3 lp = localVehiclePose(c.pose, f, &Jp, &Jv);
        PointFromLocalPoseJacobians Jh;
        const Vec2 l = pointLocalFromLocalPose(lp, c.sensor, c.z, f, &Jh);
        PointLocalJacobians Jg;
        EXPECT_LT((l - pointLocal(c.pose, c.sensor, c.z, f, &Jg)).norm(), 1e-9);

        const auto byLocalPose = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd
        { return pointLocalFromLocalPose(x, c.sensor, c.z, f); };
        const auto byZ = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd
        { return pointLocalFromLocalPose(lp, c.sensor, x, f); };
        const auto byVertices = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd
        { return pointLocalFromLocalPose(lp, c.sensor, c.z, frameOf(x)); };
        EXPECT_LT((Jh.local_pose - numericJacobian(byLocalPose, lp)).cwiseAbs().maxCoeff(), 1e-6);
        EXPECT_LT((Jh.z - numericJacobian(byZ, c.z)).cwiseAbs().maxCoeff(), 1e-6);
        EXPECT_LT((Jh.vertices - numericJacobian(byVertices, c.v)).cwiseAbs().maxCoeff(), 1e-6);

        // Chain rule: the thesis route (local pose, then Eq. 3.29) and the store's route
        // (global pose and vertices) give the same first-order model, so the same
        // covariance -- but only with the explicit vertex term Eq. 3.30 leaves out.
        EXPECT_LT((Jh.local_pose * Jp - Jg.pose).cwiseAbs().maxCoeff(), 1e-9);
        EXPECT_LT((Jh.local_pose * Jv + Jh.vertices - Jg.vertices).cwiseAbs().maxCoeff(), 1e-9);
        EXPECT_GT(Jh.vertices.cwiseAbs().maxCoeff(), 1e-3) << "h depends on the vertices at fixed x_v^L";
    }
}

TEST(LocalModelsTest, DegenerateTriangleIsRefusedWithAClearError)
{
    EXPECT_THROW(TriangleFrame(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), Eigen::Vector2d(2, 2)),
                 std::invalid_argument);
}

}  // namespace
