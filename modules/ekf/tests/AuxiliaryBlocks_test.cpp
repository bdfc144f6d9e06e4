// Auxiliary blocks (EkfSlam::addBlockCopy, relaxBlockTowards): both are linear maps of the
// joint active + passive covariance, checked entry by entry against the matrices written
// out; and a pose landmark observed with first-order Gauss-Markov (AR(1)) errors stays
// consistent when the correlated share is such a block, where the filter that takes the
// errors as independent does not.
#include <gtest/gtest.h>
#include <hymm/ekf/EkfSlam.h>
#include <hymm/ekf/pose_composition.h>
#include <hymm/ekf/pose_landmark_model.h>
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
using hymm::ekf::testing::minEigenvalue;
using hymm::ekf::testing::randomSpd;

/** [active mean; passive means] and their joint covariance. */
struct Joint
{
    Eigen::VectorXd x;
    Eigen::MatrixXd P;
};

Joint joint(const EkfSlam& f, long passive_id)
{
    const Eigen::Index n = f.mean().size(), p = f.passive().mean(passive_id).size();
    Joint j;
    j.x.resize(n + p);
    j.x << f.mean(), f.passive().mean(passive_id);
    j.P.resize(n + p, n + p);
    const Eigen::MatrixXd C = f.passive().crossCov(passive_id);
    j.P << Eigen::MatrixXd(f.cov()), C.transpose(), C, f.passive().cov(passive_id);
    return j;
}

TEST(AuxiliaryBlocksTest, CopyAndRelaxAreLinearMapsOfTheJointCovariance)
{
    std::mt19937 rng(11);
    // Vehicle, pose landmark 10, point landmark 11, pose landmark 12; one passive pose.
    const Eigen::Index n = 11, p = 3;
    const Eigen::MatrixXd S = randomSpd(rng, n + p, 0.05, 2.0);
    Eigen::VectorXd x(n);
    x << 1, 2, 0.3, 4, 5, 3.1, 7, 8, -2, 1, -3.1;
    EkfSlam f(EkfSlam::Options{});
    f.setActiveState(x, S.topLeftCorner(n, n), {{10, 3}, {11, 2}, {12, 3}});
    f.addPassiveState(99, Eigen::Vector3d(0.5, 0.6, 0.7), S.bottomRightCorner(p, p), S.bottomLeftCorner(p, n));
    const Joint before = joint(f, 99);

    // Copy of block 10 (offset 3) plus noise N0: G stacks the identity and the selector.
    const Eigen::Matrix3d N0 = randomSpd(rng, 3, 0.01, 0.1);
    const long a = f.addBlockCopy(10, N0);
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n + 3 + p, n + p);
    G.topLeftCorner(n, n).setIdentity();
    G.block(n, 3, 3, 3).setIdentity();
    G.bottomRightCorner(p, p).setIdentity();
    Eigen::MatrixXd expected = G * before.P * G.transpose();
    expected.block(n, n, 3, 3) += N0;
    const Joint copied = joint(f, 99);
    EXPECT_LT((copied.P - expected).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((copied.x - G * before.x).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_TRUE(f.layout().get(a).auxiliary);
    EXPECT_EQ(f.landmarkIds(), (std::vector<long>{10, 11, 12}));
    EXPECT_EQ(f.numLandmarks(), 3u);
    EXPECT_EQ(f.landmarkFirstEstimate(a), f.landmarkFirstEstimate(10));

    // Block 12 (offset 8, angle -3.1) relaxed towards block 10 (angle 3.1) across +-pi.
    const double rho = 0.6;
    const Eigen::Matrix3d Q = randomSpd(rng, 3, 0.01, 0.1);
    f.relaxBlockTowards(12, 10, rho, Q);
    const Eigen::Index m = n + 3 + p;
    Eigen::MatrixXd T = Eigen::MatrixXd::Identity(m, m);
    T.block(8, 8, 3, 3) = rho * Eigen::Matrix3d::Identity();
    T.block(8, 3, 3, 3) = (1 - rho) * Eigen::Matrix3d::Identity();
    expected = T * copied.P * T.transpose();
    expected.block(8, 8, 3, 3) += Q;
    const Joint relaxed = joint(f, 99);
    EXPECT_LT((relaxed.P - expected).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(relaxed.x[8], 4 + rho * (-2 - 4), 1e-12);
    EXPECT_NEAR(relaxed.x[9], 5 + rho * (1 - 5), 1e-12);
    const double dphi = mrpt::math::wrapToPi(-3.1 - 3.1);  // +0.083, not -6.2
    EXPECT_NEAR(relaxed.x[10], mrpt::math::wrapToPi(3.1 + rho * dphi), 1e-12);
    EXPECT_GT(minEigenvalue(relaxed.P), 0);

    // Bad input is refused, the state untouched.
    EXPECT_THROW(f.relaxBlockTowards(12, 11, rho, Q), std::invalid_argument);   // 3 against 2 DOF
    EXPECT_THROW(f.relaxBlockTowards(12, 12, rho, Q), std::invalid_argument);
    EXPECT_THROW(f.relaxBlockTowards(12, 10, 1.5, Q), std::invalid_argument);
    EXPECT_THROW(f.relaxBlockTowards(12, 10, rho, Eigen::Matrix3d(-Q)), std::invalid_argument);
    EXPECT_THROW(f.addBlockCopy(10, Eigen::Matrix3d(-N0)), std::invalid_argument);
    EXPECT_THROW(f.addBlockCopy(10, N0, a), std::invalid_argument);  // id in use
    EXPECT_THROW(f.addBlockCopy(77, N0), std::out_of_range);
    EXPECT_EQ(joint(f, 99).P, relaxed.P);
    f.removeLandmark(a);
    EXPECT_EQ(f.mean().size(), n);
}

/** Monte Carlo: a vehicle drives past a pose landmark and observes it every step; the
 *  observation error is b_k + w_k, b an AR(1) sequence over the viewpoint (rho per step,
 *  stationary covariance c R) and w white ((1 - c) R). Returns the mean landmark NEES at
 *  the end and the mean vehicle NEES over the steps, with the correlated share as an
 *  auxiliary block (`model`) or every observation taken as independent with R. */
std::pair<double, double> gaussMarkovRuns(bool model, int runs)
{
    const double c = 0.7, step = 0.5, length = 7.0;
    const double rho = std::exp(-step / length);
    const Eigen::Matrix3d R = Eigen::Vector3d(0.1 * 0.1, 0.1 * 0.1, std::pow(1.0 * M_PI / 180, 2)).asDiagonal();
    // Isotropic in x, y: c R is also the stationary covariance in the global frame.
    const Eigen::Matrix3d sigma = c * R, white = (1 - c) * R;
    const Eigen::Matrix3d Ls = sigma.llt().matrixL(), Lw = white.llt().matrixL();
    const Eigen::Matrix3d Q = Eigen::Vector3d(0.02 * 0.02, 0.02 * 0.02, std::pow(0.3 * M_PI / 180, 2)).asDiagonal();
    const Eigen::Matrix3d Lq = Q.llt().matrixL();
    const Eigen::Vector3d landmark(10, 6, 0.4), sensor = Eigen::Vector3d::Zero();
    std::mt19937 rng(3);
    std::normal_distribution<double> g(0, 1);
    const auto normal = [&] { return Eigen::Vector3d(g(rng), g(rng), g(rng)); };
    double lm_nees = 0, veh_nees = 0;
    int veh_n = 0;
    for (int r = 0; r < runs; ++r)
    {
        EkfSlam f(EkfSlam::Options{});
        Eigen::Vector3d truth = Eigen::Vector3d::Zero();
        f.reset(truth, Eigen::Matrix3d::Zero());
        Eigen::Vector3d b = Ls * normal();
        const auto observe = [&] {
            Eigen::Vector3d z = poseLandmarkObservation(truth, landmark + b, sensor) + Lw * normal();
            z.z() = mrpt::math::wrapToPi(z.z());
            return z;
        };
        // The creation observes the apparent pose L + b; L = A - b with b independent of A.
        long lm = -1, apparent = -1;
        if (model)
        {
            apparent = f.addPoseLandmark(observe(), white, sensor);
            lm = f.addBlockCopy(apparent, sigma);
        }
        else
            lm = f.addPoseLandmark(observe(), R, sensor);
        for (int k = 1; k <= 30; ++k)
        {
            const Eigen::Vector3d d(step, 0, 0.01);
            const Eigen::Vector3d noise = Lq * normal();
            truth = composePose(truth, Eigen::Vector3d(d + noise));
            f.predictOdometry(mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(d.x(), d.y(), d.z()),
                                                            mrpt::math::CMatrixDouble33(Q)));
            b = rho * b + std::sqrt(1 - rho * rho) * (Ls * normal());
            const Eigen::Vector3d z = observe();
            if (model)
            {
                f.relaxBlockTowards(apparent, lm, rho, (1 - rho * rho) * sigma);
                EXPECT_EQ(f.updatePoseLandmark(apparent, z, white, sensor, 0).outcome,
                          PoseUpdateReport::Outcome::updated);
            }
            else
                EXPECT_EQ(f.updatePoseLandmark(lm, z, R, sensor, 0).outcome, PoseUpdateReport::Outcome::updated);
            Eigen::Vector3d ev = f.vehiclePose() - truth;
            ev.z() = mrpt::math::wrapToPi(ev.z());
            veh_nees += ev.dot(f.vehicleCov().ldlt().solve(ev));
            ++veh_n;
        }
        Eigen::Vector3d el = f.landmarkBlockMean(lm) - landmark;
        el.z() = mrpt::math::wrapToPi(el.z());
        lm_nees += el.dot(Eigen::Matrix3d(f.landmarkBlockCov(lm)).ldlt().solve(el));
    }
    return {lm_nees / runs, veh_nees / veh_n};
}

TEST(AuxiliaryBlocksTest, GaussMarkovObservationErrorsAreConsistentAsAState)
{
    const int runs = 200;
    // 99 % band of the mean of `runs` chi-square(3) values.
    const double lo = mrpt::math::chi2inv(0.005, 3 * runs) / runs, hi = mrpt::math::chi2inv(0.995, 3 * runs) / runs;
    const auto [lm_model, veh_model] = gaussMarkovRuns(true, runs);
    const auto [lm_indep, veh_indep] = gaussMarkovRuns(false, runs);
    EXPECT_GT(lm_model, lo);
    EXPECT_LT(lm_model, hi);
    // The vehicle's NEES is averaged over 30 correlated steps: a looser band (+-25 %).
    EXPECT_GT(veh_model, 0.75 * 3);
    EXPECT_LT(veh_model, 1.25 * 3);
    // Taken as independent, the same errors make the landmark (and the vehicle, which is
    // located from it) over-confident: what the state model is for.
    EXPECT_GT(lm_indep, hi);
    EXPECT_GT(veh_indep, veh_model);
}

}  // namespace
