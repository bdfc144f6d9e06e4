/**
 * @file position_error_test.cpp
 * @brief Sec. 3.6: error of a dense point's global position through its vertices.
 */
#include "hymm/ltr/position_error.h"

#include "synthetic_map.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

namespace
{
using namespace hymm::ltr;
using V2 = Eigen::Vector2d;
using M6 = Eigen::Matrix<double, 6, 6>;

M6 randomSpd(std::mt19937& rng)
{
    std::normal_distribution<double> n(0, 0.3);
    Eigen::Matrix<double, 6, 6> a;
    for (int i = 0; i < 36; ++i) a(i) = n(rng);
    return a * a.transpose() + 0.01 * M6::Identity();
}

TEST(PositionErrorTest, GlobalCovarianceMatchesMonteCarlo)
{
    std::mt19937 rng(21);
    const TriangleFrame f(V2(0, 0), V2(10, 1), V2(3, 9));
    const M6 p = randomSpd(rng);
    const V2 local(0.3, 0.25);
    const Eigen::Matrix2d predicted = globalPositionCovariance(f, local, p);

    const Eigen::Matrix<double, 6, 6> chol = p.llt().matrixL();
    std::normal_distribution<double> n(0, 1);
    const int samples = 40000;
    Eigen::Matrix2d acc = Eigen::Matrix2d::Zero();
    const V2 x0 = f.toGlobal(local);
    for (int s = 0; s < samples; ++s)
    {
        Eigen::Matrix<double, 6, 1> e;
        for (int i = 0; i < 6; ++i) e(i) = n(rng);
        const Eigen::Matrix<double, 6, 1> dl = chol * e;
        const TriangleFrame g(
            f.vertex(0) + dl.segment<2>(0), f.vertex(1) + dl.segment<2>(2),
            f.vertex(2) + dl.segment<2>(4), FrameLimits{1e-9, 1e9});
        const V2 dx = g.toGlobal(local) - x0;
        acc += dx * dx.transpose();
    }
    acc /= samples;
    EXPECT_LT((acc - predicted).norm(), 0.05 * predicted.norm());
}

TEST(PositionErrorTest, FullyCorrelatedVerticesMoveTheRegionRigidly)
{
    // Sec. 3.3: with one common error in all vertices and in the point, the global
    // error of the point is that common error and its local coordinates are exact.
    const TriangleFrame f(V2(0, 0), V2(10, 1), V2(3, 9));
    const double s2 = 0.7;
    M6 p;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) p.block<2, 2>(2 * i, 2 * j) = s2 * Eigen::Matrix2d::Identity();
    const V2 local(0.2, 0.5);
    EXPECT_TRUE(globalPositionCovariance(f, local, p).isApprox(s2 * Eigen::Matrix2d::Identity()));
    Eigen::Matrix<double, 2, 6> p_xl;
    p_xl << s2 * Eigen::Matrix2d::Identity(), s2 * Eigen::Matrix2d::Identity(),
        s2 * Eigen::Matrix2d::Identity();
    const Eigen::Matrix2d pl = localCoordinatesCovariance(
        f, f.toGlobal(local), s2 * Eigen::Matrix2d::Identity(), p_xl, p);
    EXPECT_LT(pl.norm(), 1e-12);
    // Without correlation the local coordinates do carry error.
    const Eigen::Matrix2d pl_indep = localCoordinatesCovariance(
        f, f.toGlobal(local), s2 * Eigen::Matrix2d::Identity(), Eigen::Matrix<double, 2, 6>::Zero(),
        s2 * M6::Identity());
    EXPECT_GT(pl_indep.trace(), 1e-3);
}

TEST(PositionErrorTest, DisplacementIsTheWeightedVertexCorrection)
{
    std::mt19937 rng(22);
    std::normal_distribution<double> n(0, 0.5);
    const TriangleFrame f(V2(0, 0), V2(10, 1), V2(3, 9));
    const V2 local(0.4, 0.1);
    const std::array<V2, 3> delta{V2(n(rng), n(rng)), V2(n(rng), n(rng)), V2(n(rng), n(rng))};
    const TriangleFrame g(
        f.vertex(0) + delta[0], f.vertex(1) + delta[1], f.vertex(2) + delta[2]);
    EXPECT_LT((g.toGlobal(local) - f.toGlobal(local) - globalDisplacement(local, delta)).norm(), 1e-12);
}

TEST(PositionErrorTest, ViewOverloadReadsTheJointCovariance)
{
    const auto view = synthetic::makeSyntheticView(
        {V2(0, 0), V2(10, 1), V2(3, 9), V2(20, 20)}, Eigen::Vector3d(2, 2, 0));
    const std::array<long, 3> ids{100, 101, 102};
    const M6 p = jointVertexCovariance(view, ids);
    EXPECT_TRUE((p.block<2, 2>(2, 4).isApprox(view.crossCov(101, 102))));
    EXPECT_TRUE((p.block<2, 2>(4, 4).isApprox(view.cov(102))));
    const TriangleFrame f(view.mean(100), view.mean(101), view.mean(102));
    const V2 local(0.3, 0.3);
    EXPECT_TRUE(globalPositionCovariance(view, ids, local).isApprox(globalPositionCovariance(f, local, p)));
    // Highly correlated vertices: the point's global error is close to the common error
    // and far below the sum of independent vertex errors.
    EXPECT_NEAR(globalPositionCovariance(view, ids, local)(0, 0), 1.0, 0.05);
}

// Sec. 3.6 / 3.7.3: a return x = v + Rot(dphi) (x - v) seen from a sampled vehicle pose,
// its local coordinates in a triangle of sampled vertices; the spread of those local
// coordinates (in metres at the mean axes) is what localFusionCovariance predicts.
TEST(PositionErrorTest, LocalFusionCovarianceMatchesMonteCarlo)
{
    std::mt19937 rng(5);
    const std::vector<V2> lms{V2(0, 0), V2(12, 1), V2(4, 10)};
    const Eigen::Vector3d vehicle(3, -4, 0.3);
    const auto view = synthetic::makeSyntheticView(lms, vehicle);
    const std::array<long, 3> ids{100, 101, 102};
    const V2 x(6, 4);
    const Eigen::Matrix2d predicted = localFusionCovariance(view, ids, x);

    const Eigen::MatrixXd& cov = view.stateCov();
    const Eigen::MatrixXd l = cov.llt().matrixL();
    const TriangleFrame mean_frame(lms[0], lms[1], lms[2]);
    std::normal_distribution<double> n(0, 1);
    const int samples = 20000;
    std::vector<V2> errs;
    V2 sum = V2::Zero();
    for (int s = 0; s < samples; ++s)
    {
        Eigen::VectorXd e(cov.rows());
        for (int i = 0; i < e.size(); ++i) e(i) = n(rng);
        const Eigen::VectorXd d = l * e;
        const V2 v = vehicle.head<2>() + d.head<2>();
        const double dphi = d(2);
        // The return is fixed relative to the vehicle: it moves and turns with it.
        const V2 q = x - vehicle.head<2>();
        const V2 xs = v + Eigen::Rotation2Dd(dphi) * q;
        const TriangleFrame f(lms[0] + d.segment<2>(3), lms[1] + d.segment<2>(5), lms[2] + d.segment<2>(7));
        const V2 err = mean_frame.axes() * (f.toLocal(xs) - mean_frame.toLocal(x));
        errs.push_back(err);
        sum += err;
    }
    const V2 mean = sum / samples;
    Eigen::Matrix2d mc = Eigen::Matrix2d::Zero();
    for (const auto& e : errs) mc += (e - mean) * (e - mean).transpose();
    mc /= samples - 1;
    EXPECT_LT(mean.norm(), 0.02);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(predicted(i), mc(i), 0.05 * mc.diagonal().maxCoeff());

    // The common error (sigma 1 m) cancels: the fusion error is far below the vehicle's
    // global uncertainty, which is what lets a region take returns (Sec. 3.3).
    EXPECT_LT(std::sqrt(predicted.eigenvalues().real().maxCoeff()), 0.4);
    EXPECT_GT(view.vehicleCov()(0, 0), 1.0);
}

}  // namespace
