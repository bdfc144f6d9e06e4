// The wheels' turn bias as a filter state (EkfSlam::predictOdometryWithTurnBias) and the
// vehicle copy it is learnt through (addVehicleCopy, updateVehicleFromCopy): the
// increment's Jacobians against numeric differences, the prediction and the update as
// the linear maps they claim to be on the joint active + passive covariance, and a Monte
// Carlo of wheels that turn too little, aligned to keyframes: the bias is learnt and the
// filter stays consistent, where the same filter without the state does not.
#include <gtest/gtest.h>
#include <hymm/ekf/EkfSlam.h>
#include <hymm/core/turn_bias.h>
#include <hymm/ekf/pose_composition.h>
#include <mrpt/math/distributions.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>

#include "test_helpers.h"

namespace
{
using namespace hymm::ekf;
using hymm::core::turnBiasedIncrement;
using hymm::ekf::testing::numericJacobian;
using hymm::ekf::testing::randomSpd;

constexpr double kDeg = M_PI / 180;

mrpt::poses::CPosePDFGaussian pdf(const Eigen::Vector3d& d, const Eigen::Matrix3d& S)
{
    return mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(d.x(), d.y(), d.z()), mrpt::math::CMatrixDouble33(S));
}

/** a^-1 (+) b. */
Eigen::Vector3d relative(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
    const double c = std::cos(a.z()), s = std::sin(a.z());
    const Eigen::Vector2d d = b.head<2>() - a.head<2>();
    return {c * d.x() + s * d.y(), -s * d.x() + c * d.y(), mrpt::math::wrapToPi(b.z() - a.z())};
}

TEST(TurnBiasTest, IncrementJacobiansMatchNumericDifferences)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    for (int trial = 0; trial < 50; ++trial)
    {
        const Eigen::Vector3d d(u(rng), u(rng), 0.5 * u(rng));
        const double b = trial == 0 ? 0.0 : 0.1 * u(rng);
        Eigen::Vector3d Jb;
        Eigen::Matrix3d Jd;
        const Eigen::Vector3d out = turnBiasedIncrement(d, b, &Jb, &Jd);
        EXPECT_NEAR(out.head<2>().norm(), d.head<2>().norm(), 1e-12);  // a rotation of the chord
        EXPECT_NEAR(mrpt::math::wrapToPi(out.z() - d.z() - b * d.head<2>().norm()), 0, 1e-12);
        const Eigen::MatrixXd nb = numericJacobian(
            [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return turnBiasedIncrement(d, v[0]); },
            Eigen::VectorXd::Constant(1, b), {2});
        const Eigen::MatrixXd nd = numericJacobian(
            [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return turnBiasedIncrement(v, b); }, d, {2});
        EXPECT_LT((nb - Jb).cwiseAbs().maxCoeff(), 1e-7) << "trial " << trial;
        EXPECT_LT((nd - Jd).cwiseAbs().maxCoeff(), 1e-7) << "trial " << trial;
    }
    // A standing vehicle: no turn, and finite Jacobians.
    Eigen::Vector3d Jb;
    Eigen::Matrix3d Jd;
    EXPECT_LT((turnBiasedIncrement(Eigen::Vector3d(0, 0, 0.2), 0.05, &Jb, &Jd) - Eigen::Vector3d(0, 0, 0.2)).norm(),
              1e-15);
    EXPECT_TRUE(Jb.allFinite() && Jd.allFinite());
}

/** [active; passive 99] mean and joint covariance. */
std::pair<Eigen::VectorXd, Eigen::MatrixXd> joint(const EkfSlam& f)
{
    const Eigen::Index n = f.mean().size();
    Eigen::VectorXd x(n + 3);
    x << f.mean(), f.passive().mean(99);
    const Eigen::MatrixXd C = f.passive().crossCov(99);
    Eigen::MatrixXd P(n + 3, n + 3);
    P << Eigen::MatrixXd(f.cov()), C.transpose(), C, f.passive().cov(99);
    return {x, P};
}

TEST(TurnBiasTest, PredictionAndCopyUpdateAreTheJointModelsLinearMaps)
{
    for (const auto lin : {LinearisationPoint::Current, LinearisationPoint::FirstEstimates})
    {
        std::mt19937 rng(5);
        // Vehicle, point landmark 11, bias 12 (1-DOF); one passive pose.
        const Eigen::Index n = 6;
        Eigen::MatrixXd S = randomSpd(rng, n + 3, 0.01, 0.5);
        Eigen::VectorXd x(n);
        x << 1, 2, 3.0, 4, 5, 0.03;
        EkfSlam::Options o;
        o.jacobians = lin;
        EkfSlam f(o);
        f.setActiveState(x, S.topLeftCorner(n, n), {{11, 2}, {12, 1}});
        f.addPassiveState(99, Eigen::Vector3d(0.5, 0.6, 0.7), S.bottomRightCorner(3, 3), S.bottomLeftCorner(3, n));
        const auto [x0, P0] = joint(f);

        // Prediction: the map (x_v, b) -> x_v (+) turnBiasedIncrement(d, b), differentiated
        // numerically; everything else unchanged; b's variance grows by walk_var * |d|.
        const Eigen::Vector3d d(0.8, -0.3, 0.1);
        const Eigen::Matrix3d Sigma = randomSpd(rng, 3, 1e-4, 1e-2);
        const double walk = 1e-4;
        f.predictOdometryWithTurnBias(pdf(d, Sigma), 12, walk);
        const auto motion = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
            return composePose(v.head<3>(), turnBiasedIncrement(d, v[3]));
        };
        Eigen::VectorXd vb(4);
        vb << x.head<3>(), x[5];
        const Eigen::MatrixXd J = numericJacobian(motion, vb, {2});
        Eigen::MatrixXd T = Eigen::MatrixXd::Identity(n + 3, n + 3);
        T.topLeftCorner(3, 3) = J.leftCols(3);
        T.block(0, 5, 3, 1) = J.col(3);
        const Eigen::MatrixXd Jd = numericJacobian(
            [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return composePose(x.head<3>(), turnBiasedIncrement(v, x[5])); },
            d, {2});
        Eigen::MatrixXd expected = T * P0 * T.transpose();
        expected.topLeftCorner(3, 3) += Jd * Sigma * Jd.transpose();
        expected(5, 5) += walk * d.head<2>().norm();
        const auto [x1, P1] = joint(f);
        EXPECT_LT((P1 - expected).cwiseAbs().maxCoeff(), 1e-7);
        EXPECT_LT((x1.head<3>() - motion(vb)).cwiseAbs().maxCoeff(), 1e-12);
        EXPECT_EQ(x1.tail(n - 3 + 3), x0.tail(n - 3 + 3));

        // The copy: the vehicle's rows again.
        const long c = f.addVehicleCopy(StateLayout::kFirstReservedId);
        EXPECT_TRUE(f.layout().get(c).auxiliary);
        EXPECT_EQ(f.landmarkIds(), (std::vector<long>{11, 12}));  // setActiveState makes 12 a landmark
        EXPECT_EQ(f.layout().nextFreeId(), 13);  // a reserved id does not move the automatic ones
        const auto [x2, P2] = joint(f);
        EXPECT_EQ(x2.segment<3>(n), x2.head<3>());
        EXPECT_EQ(P2.block(n, 0, 3, n + 3), P2.topRows(3).leftCols(n + 3));

        // Move on, then observe the vehicle from the copy: the Kalman update with H the
        // numeric Jacobian of x_c^-1 (+) x_v (at x_{k|k-1} and the copy's first estimate
        // with FEJ, which for this first update are the estimate itself).
        f.predictOdometryWithTurnBias(pdf(Eigen::Vector3d(1.0, 0.1, 0.2), Sigma), 12, walk);
        const auto [x3, P3] = joint(f);
        const Eigen::Index m = P3.rows(), oc = n;
        const auto h = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
            return relative(v.segment<3>(oc), v.head<3>());
        };
        const Eigen::MatrixXd H = numericJacobian(h, x3, {2});
        const Eigen::Vector3d z = h(x3) + Eigen::Vector3d(0.05, -0.02, 0.01);
        const Eigen::Matrix3d R = randomSpd(rng, 3, 1e-4, 1e-3);
        const PoseUpdateReport rep = f.updateVehicleFromCopy(c, z, R, 0);
        ASSERT_EQ(rep.outcome, PoseUpdateReport::Outcome::updated);
        const Eigen::MatrixXd Sinn = H * P3 * H.transpose() + R;
        const Eigen::MatrixXd K = P3 * H.transpose() * Sinn.inverse();
        Eigen::Vector3d nu = z - h(x3);
        nu.z() = mrpt::math::wrapToPi(nu.z());
        const auto [x4, P4] = joint(f);
        EXPECT_LT((x4 - (x3 + K * nu)).cwiseAbs().maxCoeff(), 1e-7);
        EXPECT_LT((P4 - (Eigen::MatrixXd::Identity(m, m) - K * H) * P3).cwiseAbs().maxCoeff(), 1e-7);
        EXPECT_NEAR(rep.nis, nu.dot(Sinn.ldlt().solve(nu)), 1e-6);

        // A second observation right away: the estimates have left the points FEJ keeps
        // (the copy's first estimate and x_{k|k-1}, both as in x3), the current
        // Jacobians are at x4.
        const Eigen::MatrixXd H2 = numericJacobian(h, lin == LinearisationPoint::FirstEstimates ? x3 : x4, {2});
        const Eigen::Vector3d z2 = h(x4) + Eigen::Vector3d(-0.03, 0.02, -0.01);
        ASSERT_EQ(f.updateVehicleFromCopy(c, z2, R, 0).outcome, PoseUpdateReport::Outcome::updated);
        const Eigen::MatrixXd K2 = P4 * H2.transpose() * (H2 * P4 * H2.transpose() + R).inverse();
        Eigen::Vector3d nu2 = z2 - h(x4);
        nu2.z() = mrpt::math::wrapToPi(nu2.z());
        const auto [x5, P5] = joint(f);
        EXPECT_LT((x5 - (x4 + K2 * nu2)).cwiseAbs().maxCoeff(), 1e-7);
        EXPECT_LT((P5 - (Eigen::MatrixXd::Identity(m, m) - K2 * H2) * P4).cwiseAbs().maxCoeff(), 1e-7);

        // Copied again in place: the vehicle's rows (active and passive) and mean, and
        // the copy's first estimate.
        f.recopyVehicle(c);
        const auto [x6, P6] = joint(f);
        EXPECT_EQ(x6.segment<3>(oc), x6.head<3>());
        EXPECT_EQ(P6.middleRows(oc, 3), P6.topRows(3));
        EXPECT_EQ(P6.middleCols(oc, 3), P6.leftCols(3));
        EXPECT_EQ(f.landmarkFirstEstimate(c), Eigen::VectorXd(x6.head<3>()));
        EXPECT_THROW(f.recopyVehicle(12), std::invalid_argument);  // the 1-DOF bias

        // Bad input.
        EXPECT_THROW(f.predictOdometryWithTurnBias(pdf(d, Sigma), 11, walk), std::invalid_argument);
        EXPECT_THROW(f.predictOdometryWithTurnBias(pdf(d, Sigma), 12, -1), std::invalid_argument);
        EXPECT_THROW(f.predictOdometryWithTurnBias(pdf(Eigen::Vector3d(NAN, 0, 0), Sigma), 12, walk),
                     std::invalid_argument);
        EXPECT_EQ(f.updateVehicleFromCopy(c, Eigen::Vector3d(NAN, 0, 0), R, 0).outcome,
                  PoseUpdateReport::Outcome::invalid);
        EXPECT_THROW(f.addAuxiliaryBlock(Eigen::VectorXd::Zero(1), -Eigen::MatrixXd::Identity(1, 1)),
                     std::invalid_argument);
    }
    EkfSlam::Options inv;
    inv.jacobians = LinearisationPoint::Invariant;
    EkfSlam g(inv);
    const long b = g.addAuxiliaryBlock(Eigen::VectorXd::Zero(1), Eigen::MatrixXd::Identity(1, 1));
    EXPECT_THROW(g.predictOdometryWithTurnBias(pdf(Eigen::Vector3d(1, 0, 0), Eigen::Matrix3d::Identity()), b, 0),
                 std::invalid_argument);
}

/** One run of wheels that turn `b_true` rad/m too little, aligned to keyframes: the
 *  final error of (vehicle, bias) and its covariance, or of the vehicle alone without
 *  the state. */
struct RunResult
{
    double nees_with = 0, nees_without = 0, bias_err = 0, bias_std = 0;
};

RunResult biasedRun(std::mt19937& rng, LinearisationPoint lin)
{
    const double prior = 2 * kDeg, sxy = 0.02, sphi = 0.3 * kDeg, rxy = 0.02, rphi = 0.5 * kDeg;
    std::normal_distribution<double> g(0, 1);
    const double b_true = prior * g(rng);
    const Eigen::Matrix3d Sigma = Eigen::Vector3d(sxy * sxy, sxy * sxy, sphi * sphi).asDiagonal();
    const Eigen::Matrix3d R = Eigen::Vector3d(rxy * rxy, rxy * rxy, rphi * rphi).asDiagonal();
    EkfSlam::Options opts;
    opts.jacobians = lin;
    EkfSlam with(opts), without(opts);
    const long bias = with.addAuxiliaryBlock(Eigen::VectorXd::Zero(1), Eigen::MatrixXd::Constant(1, 1, prior * prior),
                                             StateLayout::kFirstReservedId);
    Eigen::Vector3d truth = Eigen::Vector3d::Zero(), key_truth = truth;
    long copy_with = with.addVehicleCopy(), copy_without = without.addVehicleCopy();
    for (int k = 1; k <= 60; ++k)
    {
        // Commanded step; the vehicle turns the bias on top; the wheels read the command
        // with noise.
        const Eigen::Vector3d c(0.5, 0, (k / 15) % 2 ? 0.05 : -0.03);
        truth = composePose(truth, turnBiasedIncrement(c, b_true));
        Eigen::Vector3d n;
        for (int i = 0; i < 3; ++i) n[i] = g(rng);
        const Eigen::Vector3d read = c + Sigma.diagonal().cwiseSqrt().cwiseProduct(n);
        with.predictOdometryWithTurnBias(pdf(read, Sigma), bias, 0);
        without.predictOdometry(pdf(read, Sigma));
        Eigen::Vector3d m;
        for (int i = 0; i < 3; ++i) m[i] = g(rng);
        Eigen::Vector3d z = relative(key_truth, truth) + R.diagonal().cwiseSqrt().cwiseProduct(m);
        z.z() = mrpt::math::wrapToPi(z.z());
        EXPECT_EQ(with.updateVehicleFromCopy(copy_with, z, R, 0).outcome, PoseUpdateReport::Outcome::updated);
        EXPECT_EQ(without.updateVehicleFromCopy(copy_without, z, R, 0).outcome, PoseUpdateReport::Outcome::updated);
        if (k % 3 == 0)  // a new keyframe
        {
            with.removeLandmark(copy_with);
            without.removeLandmark(copy_without);
            copy_with = with.addVehicleCopy();
            copy_without = without.addVehicleCopy();
            key_truth = truth;
        }
    }
    RunResult r;
    Eigen::Vector4d e;
    e << truth - with.vehiclePose(), b_true - with.mean()[static_cast<Eigen::Index>(with.layout().get(bias).offset)];
    e.z() = mrpt::math::wrapToPi(e.z());
    const auto ob = static_cast<Eigen::Index>(with.layout().get(bias).offset);
    Eigen::Matrix4d P;
    const Eigen::MatrixXd C = with.cov();
    const std::array<Eigen::Index, 4> idx{0, 1, 2, ob};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) P(i, j) = C(idx[i], idx[j]);
    r.nees_with = e.dot(P.ldlt().solve(e));
    r.bias_err = e[3];
    r.bias_std = std::sqrt(P(3, 3));
    Eigen::Vector3d e0 = truth - without.vehiclePose();
    e0.z() = mrpt::math::wrapToPi(e0.z());
    r.nees_without = e0.dot(without.vehicleCov().ldlt().solve(e0));
    return r;
}

TEST(TurnBiasTest, BiasIsLearntFromKeyframeAlignmentsAndTheFilterStaysConsistent)
{
  for (const auto lin : {LinearisationPoint::Current, LinearisationPoint::FirstEstimates})
  {
    std::mt19937 rng(17);
    const int runs = 200;
    double with = 0, without = 0, z2 = 0, std_sum = 0;
    for (int i = 0; i < runs; ++i)
    {
        const RunResult r = biasedRun(rng, lin);
        with += r.nees_with / runs;
        without += r.nees_without / runs;
        z2 += r.bias_err * r.bias_err / (r.bias_std * r.bias_std) / runs;
        std_sum += r.bias_std / runs;
    }
    // Mean NEES of (vehicle, bias) inside the 99 % band of chi-square(4 runs) / runs.
    EXPECT_GT(with, mrpt::math::chi2inv(0.005, 4 * runs) / runs);
    EXPECT_LT(with, mrpt::math::chi2inv(0.995, 4 * runs) / runs);
    EXPECT_LT(z2, mrpt::math::chi2inv(0.995, runs) / runs);
    // Learnt: from a 2 deg/m prior to a fraction of it over 30 m.
    EXPECT_LT(std_sum, 0.5 * 2 * kDeg);
    // Without the state the same alignments leave the vehicle over-confident.
    EXPECT_GT(without, 3 * mrpt::math::chi2inv(0.995, 3 * runs) / runs);
    std::printf("mean NEES: with the bias state %.2f (4 expected), without %.2f (3 expected); bias std %.3f deg/m\n",
                with, without, std_sum / kDeg);
  }
}

}  // namespace
