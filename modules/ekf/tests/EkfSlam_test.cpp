// Prediction, update, augmentation, removal, options and bad input of EkfSlam, each
// checked against a dense textbook reference.
#include "test_helpers.h"

#include <gtest/gtest.h>
#include <hymm/core/RangeBearingModel.h>
#include <hymm/core/UteVehicleModel.h>
#include <hymm/ekf/EkfSlam.h>
#include <hymm/ekf/pose_composition.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <limits>
#include <random>

namespace
{
using namespace hymm::ekf;
using hymm::ekf::testing::minEigenvalue;
using hymm::ekf::testing::randomSpd;

constexpr double kDeg = M_PI / 180.0;
const mrpt::poses::CPose3D kSensor(0.4, -0.1, 0.0, 5.0 * kDeg, 0.0, 0.0);

/** A filter with a random PSD covariance over the vehicle and `n_lm` point landmarks
 *  (ids 10, 11, ...) scattered 5-25 m around the vehicle. */
EkfSlam randomFilter(std::mt19937& rng, int n_lm, EkfSlam::Options opts = {})
{
    EkfSlam f(opts);
    const Eigen::Index n = 3 + 2 * n_lm;
    Eigen::VectorXd x(n);
    x.head<3>() << 1.0, -2.0, 0.7;
    std::uniform_real_distribution<double> r(5.0, 25.0), a(-M_PI, M_PI);
    std::vector<std::pair<long, int>> blocks;
    for (int k = 0; k < n_lm; ++k)
    {
        const double rr = r(rng), aa = a(rng);
        x.segment<2>(3 + 2 * k) << x[0] + rr * std::cos(aa), x[1] + rr * std::sin(aa);
        blocks.emplace_back(10 + k, 2);
    }
    Eigen::MatrixXd P = randomSpd(rng, n, 1e-3, 0.5);
    f.setActiveState(x, P, blocks);
    return f;
}

Eigen::Vector3d sensorVec() { return Eigen::Vector3d(kSensor.x(), kSensor.y(), kSensor.yaw()); }

TEST(EkfSlamTest, UtePredictionMatchesDenseReferenceAndLeavesMapUntouched)
{
    std::mt19937 rng(1);
    EkfSlam f = randomFilter(rng, 6);
    const Eigen::VectorXd x0 = f.mean();
    const Eigen::MatrixXd P0 = f.cov();
    const Eigen::Vector2d u(3.0, 0.1);
    Eigen::Matrix2d Q;
    Q << 0.04, 0.001, 0.001, 0.0009;
    const hymm::core::UteParams p;
    f.predictUte(u, Q, 0.1, p);

    Eigen::Matrix3d F;
    Eigen::Matrix<double, 3, 2> B;
    const Eigen::Vector3d pose = hymm::core::uteStep(x0.head<3>(), u, 0.1, p, &F, &B);
    const Eigen::Index n = x0.size();
    Eigen::MatrixXd Fb = Eigen::MatrixXd::Identity(n, n), Gb = Eigen::MatrixXd::Zero(n, 2);
    Fb.topLeftCorner<3, 3>() = F;
    Gb.topRows<3>() = B;
    const Eigen::MatrixXd Pref = Fb * P0 * Fb.transpose() + Gb * Q * Gb.transpose();

    EXPECT_EQ(f.vehiclePose(), pose);
    EXPECT_LT((f.cov() - Pref).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_TRUE(f.mean().tail(n - 3) == x0.tail(n - 3));
    EXPECT_TRUE(f.cov().bottomRightCorner(n - 3, n - 3) == P0.bottomRightCorner(n - 3, n - 3));
    EXPECT_TRUE(f.cov() == f.cov().transpose());
}

TEST(EkfSlamTest, OdometryPredictionMatchesDenseReferenceAndMrptAction)
{
    std::mt19937 rng(2);
    EkfSlam f = randomFilter(rng, 4);
    EkfSlam g = f;
    const Eigen::VectorXd x0 = f.mean();
    const Eigen::MatrixXd P0 = f.cov();
    mrpt::math::CMatrixDouble33 C;
    C.asEigen() = randomSpd(rng, 3, 1e-4, 1e-2);
    const mrpt::poses::CPosePDFGaussian inc(mrpt::poses::CPose2D(0.5, 0.05, 0.1), C);
    f.predictOdometry(inc);

    Eigen::Matrix3d Jx, Jd;
    const Eigen::Vector3d pose = composePose(x0.head<3>(), Eigen::Vector3d(0.5, 0.05, 0.1), &Jx, &Jd);
    const Eigen::Index n = x0.size();
    Eigen::MatrixXd Fb = Eigen::MatrixXd::Identity(n, n), Gb = Eigen::MatrixXd::Zero(n, 3);
    Fb.topLeftCorner<3, 3>() = Jx;
    Gb.topRows<3>() = Jd;
    const Eigen::MatrixXd Pref = Fb * P0 * Fb.transpose() + Gb * C.asEigen() * Gb.transpose();
    EXPECT_LT((f.vehiclePose() - pose).norm(), 1e-12);
    EXPECT_LT((f.cov() - Pref).cwiseAbs().maxCoeff(), 1e-12);

    mrpt::obs::CActionRobotMovement2D act;
    act.poseChange = mrpt::poses::CPosePDF::Ptr(std::make_shared<mrpt::poses::CPosePDFGaussian>(inc));
    g.predictOdometry(act);
    EXPECT_TRUE(g.mean() == f.mean());
    EXPECT_TRUE(g.cov() == f.cov());
}

TEST(EkfSlamTest, StabilisingNoiseIsAdded)
{
    EkfSlam::Options o;
    o.stabilising_std_xy = 0.1;
    o.stabilising_std_phi = 1.0 * kDeg;
    EkfSlam f(o);
    f.reset(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero());
    mrpt::poses::CPosePDFGaussian inc(mrpt::poses::CPose2D(1, 0, 0));
    f.predictOdometry(inc);
    EXPECT_NEAR(f.vehicleCov()(0, 0), 0.01, 1e-15);
    EXPECT_NEAR(f.vehicleCov()(2, 2), kDeg * kDeg, 1e-15);
}

/** Naive dense EKF update: dense H, K = P H^T S^-1, P = (I - K H) P symmetrised. */
void denseUpdate(Eigen::VectorXd& x, Eigen::MatrixXd& P, const std::vector<RangeBearingObs>& obs,
                 const EkfSlam& f)
{
    const Eigen::Index n = x.size(), M = static_cast<Eigen::Index>(2 * obs.size());
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(M, n), R = Eigen::MatrixXd::Zero(M, M);
    Eigen::VectorXd nu(M);
    for (size_t a = 0; a < obs.size(); ++a)
    {
        const auto o = static_cast<Eigen::Index>(f.landmarkBlock(obs[a].id).offset);
        hymm::core::Mat23 Hv;
        hymm::core::Mat2 Hl;
        const Eigen::Vector2d h = hymm::core::observeRangeBearing(
            x.head<3>(), sensorVec(), x.segment<2>(o), &Hv, &Hl);
        const auto r = static_cast<Eigen::Index>(2 * a);
        H.block<2, 3>(r, 0) = Hv;
        H.block<2, 2>(r, o) = Hl;
        R.block<2, 2>(r, r) = obs[a].R;
        nu.segment<2>(r) << obs[a].z[0] - h[0], mrpt::math::wrapToPi(obs[a].z[1] - h[1]);
    }
    const Eigen::MatrixXd S = H * P * H.transpose() + R;
    const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
    x += K * nu;
    x[2] = mrpt::math::wrapToPi(x[2]);
    P = (Eigen::MatrixXd::Identity(n, n) - K * H) * P;
    P = (0.5 * (P + P.transpose())).eval();
}

TEST(EkfSlamTest, BatchedSparseUpdateMatchesDenseTextbookUpdate)
{
    std::mt19937 rng(3);
    for (int trial = 0; trial < 5; ++trial)
    {
        EkfSlam f = randomFilter(rng, 8);
        Eigen::VectorXd x = f.mean();
        Eigen::MatrixXd P = f.cov();
        std::normal_distribution<double> g(0.0, 1.0);
        std::vector<RangeBearingObs> obs;
        for (long id : {10L, 12L, 13L, 16L, 17L})
        {
            RangeBearingObs o;
            o.id = id;
            o.R = Eigen::Vector2d(0.05, 0.5 * kDeg).cwiseAbs2().asDiagonal();
            o.z = hymm::core::observeRangeBearing(f.vehiclePose(), sensorVec(), f.landmarkMean(id));
            o.z += Eigen::Vector2d(0.3 * g(rng), 0.05 * g(rng));
            obs.push_back(o);
        }
        const UpdateReport rep = f.updateRangeBearing(obs, kSensor);
        ASSERT_EQ(rep.associated, obs.size());
        denseUpdate(x, P, obs, f);
        EXPECT_LT((f.mean() - x).cwiseAbs().maxCoeff(), 1e-9);
        EXPECT_LT((f.cov() - P).cwiseAbs().maxCoeff(), 1e-9);
        EXPECT_TRUE(f.cov() == f.cov().transpose());
        EXPECT_GT(minEigenvalue(f.cov()), -1e-12);
        for (size_t i = 0; i < obs.size(); ++i) EXPECT_EQ(rep.assigned_ids[i], obs[i].id);
    }
}

TEST(EkfSlamTest, AugmentationMatchesDenseJacobianForm)
{
    std::mt19937 rng(4);
    EkfSlam f = randomFilter(rng, 3);
    const Eigen::VectorXd x0 = f.mean();
    const Eigen::MatrixXd P0 = f.cov();
    std::vector<RangeBearingObs> obs(2);
    obs[0].z << 8.0, 0.3;
    obs[0].R = Eigen::Vector2d(0.1, 1.0 * kDeg).cwiseAbs2().asDiagonal();
    obs[0].id = 50;
    obs[1].z << 12.0, -2.0;
    obs[1].R << 0.02, 0.001, 0.001, 0.0004;
    obs[1].id = 51;
    const UpdateReport rep = f.updateRangeBearing(obs, kSensor);
    ASSERT_EQ(rep.created, 2u);

    // Augmented state y = [x; g(x_v, z1); g(x_v, z2)], Jacobian [I; G_v1 0; G_v2 0] wrt x
    // and [0; G_z1 0; 0 G_z2] wrt (z1, z2) (Eq. 2.53).
    const Eigen::Index n = x0.size();
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n + 4, n), Jz = Eigen::MatrixXd::Zero(n + 4, 4);
    Eigen::MatrixXd Rz = Eigen::MatrixXd::Zero(4, 4);
    J.topRows(n).setIdentity();
    Eigen::VectorXd xref(n + 4);
    xref.head(n) = x0;
    for (int a = 0; a < 2; ++a)
    {
        hymm::core::Mat23 Gv;
        hymm::core::Mat2 Gz;
        xref.segment<2>(n + 2 * a) =
            hymm::core::inverseRangeBearing(x0.head<3>(), sensorVec(), obs[a].z, &Gv, &Gz);
        J.block<2, 3>(n + 2 * a, 0) = Gv;
        Jz.block<2, 2>(n + 2 * a, 2 * a) = Gz;
        Rz.block<2, 2>(2 * a, 2 * a) = obs[a].R;
    }
    const Eigen::MatrixXd Pref = J * P0 * J.transpose() + Jz * Rz * Jz.transpose();
    EXPECT_LT((f.mean() - xref).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((f.cov() - Pref).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(f.landmarkBlock(51).offset, static_cast<size_t>(n + 2));
    EXPECT_GT(minEigenvalue(f.cov()), -1e-12);
}

TEST(EkfSlamTest, StorageGrowthAndInPlaceRemovalKeepEveryEntry)
{
    // The covariance lives in storage with spare capacity (grown 1.5x from 64 states):
    // many additions (crossing several growths) and removals at random positions, each
    // checked against a dense copy kept by hand. Untouched entries must be bit-identical.
    std::mt19937 rng(11);
    EkfSlam f = randomFilter(rng, 2);
    Eigen::MatrixXd Pref = f.cov();
    Eigen::VectorXd xref = f.mean();
    std::uniform_real_distribution<double> u(-1.0, 1.0), coin(0.0, 1.0);
    for (int it = 0; it < 300; ++it)
    {
        const Eigen::Index n = Pref.rows();
        if (coin(rng) < 0.3 && f.numLandmarks() > 1)
        {
            const std::vector<long> ids = f.landmarkIds();
            const long id = ids[static_cast<size_t>(coin(rng) * static_cast<double>(ids.size())) % ids.size()];
            const auto o = static_cast<Eigen::Index>(f.landmarkBlock(id).offset);
            const Eigen::Index d = f.landmarkBlock(id).dim, t = n - o - d;
            f.removeLandmark(id);
            Eigen::MatrixXd Q(n - d, n - d);
            Q << Pref.topLeftCorner(o, o), Pref.topRightCorner(o, t), Pref.bottomLeftCorner(t, o),
                Pref.bottomRightCorner(t, t);
            Pref = Q;
            Eigen::VectorXd y(n - d);
            y << xref.head(o), xref.tail(t);
            xref = y;
        }
        else
        {
            const int d = coin(rng) < 0.2 ? 3 : 2;
            Eigen::VectorXd mean(d);
            Eigen::MatrixXd G(d, 3);
            for (int i = 0; i < d; ++i) mean[i] = 10.0 * u(rng);
            for (int i = 0; i < d * 3; ++i) G(i) = u(rng);
            const Eigen::MatrixXd noise = randomSpd(rng, d, 1e-3, 0.1);
            f.addLandmark(mean, G, noise);
            ASSERT_EQ(f.cov().rows(), n + d);
            // The old block is kept bit for bit; the new rows follow Eq. 2.53.
            EXPECT_TRUE(f.cov().topLeftCorner(n, n) == Pref) << "iteration " << it;
            const Eigen::MatrixXd cross = G * Pref.topRows<3>();
            const Eigen::MatrixXd Pnn = G * Pref.topLeftCorner<3, 3>() * G.transpose() + noise;
            EXPECT_LT((f.cov().bottomLeftCorner(d, n) - cross).cwiseAbs().maxCoeff(), 1e-12);
            EXPECT_LT((f.cov().bottomRightCorner(d, d) - Pnn).cwiseAbs().maxCoeff(), 1e-12);
            Pref = f.cov();
            xref.conservativeResize(n + d);
            xref.tail(d) = mean;
        }
        ASSERT_TRUE(f.cov() == Pref) << "iteration " << it;
        ASSERT_TRUE(f.mean() == xref) << "iteration " << it;
        ASSERT_TRUE(f.cov() == f.cov().transpose()) << "iteration " << it;
    }
    EXPECT_GT(f.cov().rows(), 216);  // crossed the growths 64 -> 96 -> 144 -> 216 -> 324
    // A copy is an independent filter with the same state.
    EkfSlam g(f);
    EXPECT_TRUE(g.cov() == f.cov());
    g.removeLandmark(g.landmarkIds().front());
    EXPECT_TRUE(f.cov() == Pref);
}

TEST(EkfSlamTest, GenericBlockAugmentationAndRemovalKeepTheRestIntact)
{
    std::mt19937 rng(5);
    EkfSlam f = randomFilter(rng, 3);
    const Eigen::MatrixXd P0 = f.cov();
    const Eigen::VectorXd x0 = f.mean();
    // A 3-DOF pose landmark at the vehicle pose plus noise (G_v = I).
    const Eigen::Matrix3d noise = 0.01 * Eigen::Matrix3d::Identity();
    const long id = f.addLandmark(f.vehiclePose(), Eigen::Matrix3d::Identity(), noise);
    EXPECT_EQ(f.landmarkBlock(id).dim, 3);
    EXPECT_LT((f.landmarkBlockCov(id) - (P0.topLeftCorner<3, 3>() + noise)).norm(), 1e-14);
    EXPECT_THROW(f.landmarkMean(id), std::invalid_argument);
    f.removeLandmark(11);
    f.removeLandmark(id);
    // Remaining: vehicle, landmarks 10 and 12: the original rows/columns 0-4 and 7-8.
    const std::vector<Eigen::Index> keep{0, 1, 2, 3, 4, 7, 8};
    ASSERT_EQ(f.cov().rows(), 7);
    for (size_t i = 0; i < keep.size(); ++i)
    {
        EXPECT_EQ(f.mean()[static_cast<Eigen::Index>(i)], x0[keep[i]]);
        for (size_t j = 0; j < keep.size(); ++j)
            EXPECT_EQ(f.cov()(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)),
                      P0(keep[i], keep[j]));
    }
    EXPECT_EQ(f.landmarkIds(), (std::vector<long>{10, 12}));
    EXPECT_THROW(f.removeLandmark(11), std::out_of_range);
}

TEST(EkfSlamTest, InvalidObservationsAreSkippedAndCounted)
{
    std::mt19937 rng(6);
    EkfSlam f = randomFilter(rng, 2);
    const Eigen::VectorXd x0 = f.mean();
    std::vector<RangeBearingObs> obs(4);
    obs[0].z << std::numeric_limits<double>::quiet_NaN(), 0.1;
    obs[1].z << 5.0, 0.1;
    obs[1].R << 1.0, 0.0, 0.0, -1.0;  // not PD
    obs[2].z << 5.0, 0.1;
    obs[2].R << 1.0, 2.0, 2.0, 1.0;   // indefinite
    obs[3].z << -1.0, 0.1;            // negative range
    const UpdateReport rep = f.updateRangeBearing(obs, kSensor);
    EXPECT_EQ(rep.rejected_invalid, 4u);
    EXPECT_EQ(rep.created + rep.associated, 0u);
    EXPECT_TRUE(f.mean() == x0);
}

TEST(EkfSlamTest, NonPositiveInnovationCovarianceRejectsUpdateWithoutNaN)
{
    EkfSlam f{EkfSlam::Options{}};
    Eigen::VectorXd x(5);
    x << 0, 0, 0, 10, 0;
    Eigen::MatrixXd P = Eigen::MatrixXd::Zero(5, 5);
    P(3, 3) = -5.0;  // a broken (indefinite) covariance
    f.setActiveState(x, P, {{0, 2}});
    RangeBearingObs o;
    o.z << 10.0, 0.0;
    o.R = 1e-4 * Eigen::Matrix2d::Identity();
    o.id = 0;
    const UpdateReport rep = f.updateRangeBearing({o}, mrpt::poses::CPose3D());
    EXPECT_EQ(rep.rejected_numeric, 1u);
    EXPECT_FALSE(rep.rejection_reason.empty());
    EXPECT_EQ(rep.assigned_ids[0], -1);
    EXPECT_TRUE(f.mean() == x);
    EXPECT_TRUE(f.mean().allFinite() && f.cov().allFinite());
}

TEST(EkfSlamTest, OptionsLoadStrictlyFromIni)
{
    mrpt::config::CConfigFileMemory cfg(std::string(
        "[EkfSlam]\nassociation_method = jcbb\nassociation_gate_prob = 0.95\n"
        "creation_gate_prob = 0.999\nstabilising_std_phi_deg = 2\nconfirm_window_steps = 7\n"));
    EkfSlam::Options o;
    o.loadFromConfigFile(cfg, "EkfSlam");
    EXPECT_EQ(o.association_method, AssociationMethod::JCBB);
    EXPECT_DOUBLE_EQ(o.association_gate_prob, 0.95);
    EXPECT_NEAR(o.stabilising_std_phi, 2.0 * kDeg, 1e-15);
    EXPECT_EQ(o.confirm_window_steps, 7);

    mrpt::config::CConfigFileMemory round;
    o.saveToConfigFile(round, "EkfSlam");
    EkfSlam::Options o2;
    o2.loadFromConfigFile(round, "EkfSlam");
    EXPECT_EQ(o2.association_method, o.association_method);
    EXPECT_NEAR(o2.stabilising_std_phi, o.stabilising_std_phi, 1e-12);

    EkfSlam::Options bad;
    mrpt::config::CConfigFileMemory typo(std::string("[EkfSlam]\nassociation_gate = 0.9\n"));
    EXPECT_THROW(bad.loadFromConfigFile(typo, "EkfSlam"), std::exception);
    mrpt::config::CConfigFileMemory order(
        std::string("[EkfSlam]\nassociation_gate_prob = 0.99\ncreation_gate_prob = 0.9\n"));
    EXPECT_THROW(bad.loadFromConfigFile(order, "EkfSlam"), std::invalid_argument);
    mrpt::config::CConfigFileMemory method(std::string("[EkfSlam]\nassociation_method = best\n"));
    EXPECT_THROW(bad.loadFromConfigFile(method, "EkfSlam"), std::invalid_argument);
}

TEST(EkfSlamTest, IndefiniteOdometryCovarianceAndNonFiniteSensorPoseAreRefused)
{
    // A negative variance would leave the filter's covariance indefinite; a NaN sensor
    // mount would put every prediction at NaN. Both are refused before any state changes.
    EkfSlam f{EkfSlam::Options{}};
    const Eigen::VectorXd x0 = f.mean();
    mrpt::math::CMatrixDouble33 C;
    C.setZero();
    C(0, 0) = -1e-2;
    C(1, 1) = C(2, 2) = 1e-4;
    EXPECT_THROW(f.predictOdometry(mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(1, 0, 0), C)),
                 std::invalid_argument);
    RangeBearingObs o;
    o.z << 10.0, 0.0;
    o.R = 1e-4 * Eigen::Matrix2d::Identity();
    EXPECT_THROW(f.updateRangeBearing({o}, mrpt::poses::CPose3D(std::nan(""), 0, 0, 0, 0, 0)),
                 std::invalid_argument);
    EXPECT_TRUE(f.mean() == x0);
    EXPECT_EQ(f.numLandmarks(), 0u);
}

}  // namespace
