// Passive states (UIF, thesis 3.7.1): the active filter is unaffected bit for bit, and
// the passive blocks equal the corresponding marginals of a full joint filter in which
// the same blocks are ordinary (never observed) states.
#include <gtest/gtest.h>
#include <hymm/core/RangeBearingModel.h>
#include <hymm/ekf/EkfSlam.h>

#include <map>
#include <random>

namespace
{
using namespace hymm::ekf;

const mrpt::poses::CPose3D kSensor(0.3, 0.1, 0.0, 0.05, 0.0, 0.0);
const Eigen::Vector3d kSensorVec(0.3, 0.1, 0.05);

struct World
{
    std::vector<Eigen::Vector2d> lms;
    Eigen::Vector3d pose{0.0, 0.0, 0.0};
    std::mt19937 rng{7};
};

std::vector<RangeBearingObs> sense(World& w, bool known_ids)
{
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<RangeBearingObs> out;
    for (size_t k = 0; k < w.lms.size(); ++k)
    {
        const Eigen::Vector2d z =
            hymm::core::observeRangeBearing(w.pose, kSensorVec, w.lms[k]);
        if (z[0] > 25.0) continue;
        RangeBearingObs o;
        o.R = Eigen::Vector2d(0.1, 0.01).cwiseAbs2().asDiagonal();
        o.z = z + Eigen::Vector2d(0.1 * g(w.rng), 0.01 * g(w.rng));
        o.id = known_ids ? static_cast<long>(k) : -1;
        out.push_back(o);
    }
    return out;
}

/** Drives three filters through the same steps: plain, with passive blocks, and a joint
 *  filter holding the passive blocks as active landmarks (ids 1000+). */
struct Trio
{
    explicit Trio(const EkfSlam::Options& o) : plain(o), uif(o), joint(o) {}
    EkfSlam plain, uif, joint;
    std::map<long, long> joint_id;  // passive id -> id of the same block in `joint`

    void reset()
    {
        for (EkfSlam* f : {&plain, &uif, &joint})
            f->reset(Eigen::Vector3d::Zero(), 1e-4 * Eigen::Matrix3d::Identity());
    }
    void predict(const Eigen::Vector2d& u)
    {
        const Eigen::Matrix2d Q = Eigen::Vector2d(0.1, 0.02).cwiseAbs2().asDiagonal();
        for (EkfSlam* f : {&plain, &uif, &joint}) f->predictUte(u, Q, 0.1, hymm::core::UteParams{});
    }
    void update(const std::vector<RangeBearingObs>& obs)
    {
        for (EkfSlam* f : {&plain, &uif, &joint}) f->updateRangeBearing(obs, kSensor);
    }
    void addPassive(long id, const Eigen::VectorXd& mean, const Eigen::MatrixXd& G,
                    const Eigen::MatrixXd& noise)
    {
        uif.addPassiveFromVehicle(id, mean, G, noise);
        joint_id[id] = joint.addLandmark(mean, G, noise, 1000 + id);
    }
};

void checkPassiveStates(LinearisationPoint jacobians)
{
    World w;
    for (int k = 0; k < 12; ++k)
        w.lms.emplace_back(5.0 + 3.0 * k, (k % 2 ? 6.0 : -6.0) + 0.3 * k);
    EkfSlam::Options opts;
    opts.jacobians = jacobians;
    Trio t(opts);
    t.reset();
    const Eigen::Vector2d u(4.0, 0.02);
    for (int step = 0; step < 40; ++step)
    {
        w.pose = hymm::core::uteStep(w.pose, u, 0.1, hymm::core::UteParams{});
        t.predict(u);
        t.update(sense(w, true));
        if (step == 3)  // a copy of the vehicle pose (3-DOF) and a point seen from it
        {
            t.addPassive(1, t.uif.vehiclePose(), Eigen::Matrix3d::Identity(),
                         1e-4 * Eigen::Matrix3d::Identity());
            hymm::core::Mat23 Gv;
            hymm::core::Mat2 Gz;
            const Eigen::Vector2d z(7.0, 0.4);
            const Eigen::Vector2d p =
                hymm::core::inverseRangeBearing(t.uif.vehiclePose(), kSensorVec, z, &Gv, &Gz);
            const Eigen::Matrix2d R = Eigen::Vector2d(0.1, 0.01).cwiseAbs2().asDiagonal();
            t.addPassive(2, p, Gv, Gz * R * Gz.transpose());
        }
        if (step == 12)
            t.addPassive(3, t.uif.vehiclePose().head<2>(), Eigen::Matrix<double, 2, 3>::Identity(),
                         Eigen::Matrix2d::Zero());
        if (step == 20)
            for (EkfSlam* f : {&t.plain, &t.uif, &t.joint}) f->removeLandmark(2);
        if (step == 25)
        {
            t.uif.removePassiveState(3);
            t.joint.removeLandmark(t.joint_id[3]);
            t.joint_id.erase(3);
        }
    }
    // Bitwise: the active part never reads anything from the passive blocks.
    EXPECT_TRUE(t.uif.mean() == t.plain.mean());
    EXPECT_TRUE(t.uif.cov() == t.plain.cov());
    ASSERT_EQ(t.uif.passive().numBlocks(), 2u);

    // Passive marginals against the joint filter (different rounding: 1e-9).
    const std::vector<long> active_ids = t.uif.landmarkIds();
    for (const auto& [pid, jid] : t.joint_id)
    {
        const LandmarkBlock& jb = t.joint.landmarkBlock(jid);
        const auto jo = static_cast<Eigen::Index>(jb.offset);
        EXPECT_LT((t.uif.passive().mean(pid) - t.joint.landmarkBlockMean(jid)).norm(), 1e-9);
        EXPECT_LT((t.uif.passive().cov(pid) - t.joint.landmarkBlockCov(jid)).cwiseAbs().maxCoeff(),
                  1e-9);
        const Eigen::MatrixXd cross = t.uif.passive().crossCov(pid);
        EXPECT_LT((cross.leftCols<3>() - t.joint.cov().block(jo, 0, jb.dim, 3)).cwiseAbs().maxCoeff(),
                  1e-9);
        for (long id : active_ids)
        {
            const auto ao = static_cast<Eigen::Index>(t.uif.landmarkBlock(id).offset);
            const auto jao = static_cast<Eigen::Index>(t.joint.landmarkBlock(id).offset);
            EXPECT_LT((cross.middleCols<2>(ao) - t.joint.cov().block(jo, jao, jb.dim, 2))
                          .cwiseAbs()
                          .maxCoeff(),
                      1e-9);
        }
    }
    // Only N_p x n_active cross terms plus the own blocks are stored (no passive-passive).
    const size_t n = static_cast<size_t>(t.uif.mean().size());
    EXPECT_EQ(t.uif.passive().storedCovarianceEntries(), (3 + 2) * n + 9 + 4);
}

TEST(PassiveStatesTest, ActiveFilterIsBitwiseIdenticalAndPassiveMatchesJointFilter)
{
    checkPassiveStates(LinearisationPoint::Current);
}

TEST(PassiveStatesTest, SameWithFirstEstimatesJacobians)
{
    // FEJ-EKF: the passive blocks see the same (first-estimates) H and motion Jacobians.
    checkPassiveStates(LinearisationPoint::FirstEstimates);
}

TEST(PassiveStatesTest, SameWithTheInvariantEkf)
{
    // Right-invariant EKF: the passive positions are retracted with the same V and the
    // passive rows carried by the same M as the joint filter's.
    checkPassiveStates(LinearisationPoint::Invariant);
}

TEST(PassiveStatesTest, RejectsBadBlocks)
{
    EkfSlam f{EkfSlam::Options{}};
    f.reset(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity());
    EXPECT_THROW(f.addPassiveState(1, Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity(),
                                   Eigen::MatrixXd::Zero(2, 4)),
                 std::invalid_argument);
    Eigen::Matrix2d asym;
    asym << 1, 0.5, 0, 1;
    EXPECT_THROW(
        f.addPassiveState(1, Eigen::Vector2d::Zero(), asym, Eigen::MatrixXd::Zero(2, 3)),
        std::invalid_argument);
    f.addPassiveState(1, Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity(),
                      Eigen::MatrixXd::Zero(2, 3));
    EXPECT_THROW(f.addPassiveState(1, Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity(),
                                   Eigen::MatrixXd::Zero(2, 3)),
                 std::invalid_argument);
    EXPECT_THROW(f.removePassiveState(5), std::out_of_range);
}

TEST(PassiveStatesTest, CrossCovColumnsAreTheMatchingBlock)
{
    PassiveStates ps;
    const size_t n_active = 7;
    Eigen::MatrixXd cross(2, n_active);
    for (Eigen::Index c = 0; c < cross.cols(); ++c) cross.col(c) << 0.1 * c, -0.2 * c;
    ps.add(3, Eigen::Vector2d(1, 2), Eigen::Matrix2d::Identity(), cross, n_active);
    EXPECT_TRUE(ps.crossCov(3, 0, 3) == ps.crossCov(3).leftCols(3));
    EXPECT_TRUE(ps.crossCov(3, 5, 2) == cross.middleCols(5, 2));
    EXPECT_THROW(ps.crossCov(3, 6, 2), std::out_of_range);
    EXPECT_THROW(ps.crossCov(4, 0, 2), std::out_of_range);
}

// A passive block defined on two landmarks (a virtual landmark, thesis Sec. 3.5.1): it is
// the linear map A = [.. G_a .. G_b ..] of the joint state, so cov = A P A^T + noise and
// cross = A P (Eq. 2.53 with the landmarks in place of the vehicle); the active filter is
// untouched.
TEST(PassiveStatesTest, PassiveBlockFromLandmarksIsTheLinearMapOfTheJointState)
{
    World w;
    for (int k = 0; k < 8; ++k) w.lms.emplace_back(4.0 + 2.5 * k, (k % 2 ? 5.0 : -5.0));
    EkfSlam f{EkfSlam::Options{}};
    f.reset(Eigen::Vector3d::Zero(), 1e-4 * Eigen::Matrix3d::Identity());
    const Eigen::Vector2d u(4.0, 0.02);
    const Eigen::Matrix2d Q = Eigen::Vector2d(0.1, 0.02).cwiseAbs2().asDiagonal();
    for (int step = 0; step < 15; ++step)
    {
        w.pose = hymm::core::uteStep(w.pose, u, 0.1, hymm::core::UteParams{});
        f.predictUte(u, Q, 0.1, hymm::core::UteParams{});
        f.updateRangeBearing(sense(w, true), kSensor);
    }
    ASSERT_GE(f.numLandmarks(), 4u);
    const long a = f.landmarkIds()[1], b = f.landmarkIds()[3];
    Eigen::Matrix2d Ga, Gb;
    Ga << 0.5, -0.3, 0.2, 0.7;
    Gb << 0.4, 0.1, -0.6, 0.5;
    const Eigen::Vector2d mean = 0.5 * (f.landmarkMean(a) + f.landmarkMean(b));
    const Eigen::Matrix2d noise = 0.01 * Eigen::Matrix2d::Identity();
    const Eigen::VectorXd x_before = f.mean();
    const Eigen::MatrixXd P = f.cov();
    f.addPassiveFromLandmarks(42, mean, {{a, Ga}, {b, Gb}}, noise);

    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2, P.cols());
    A.middleCols(static_cast<Eigen::Index>(f.landmarkBlock(a).offset), 2) = Ga;
    A.middleCols(static_cast<Eigen::Index>(f.landmarkBlock(b).offset), 2) = Gb;
    const Eigen::MatrixXd cov = A * P * A.transpose() + noise;
    EXPECT_TRUE(f.passive().mean(42) == mean);
    EXPECT_LT((f.passive().cov(42) - cov).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((f.passive().crossCov(42) - A * P).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_TRUE(f.passive().cov(42) == f.passive().cov(42).transpose());
    EXPECT_TRUE(f.mean() == x_before);
    EXPECT_TRUE(f.cov() == P);

    EXPECT_THROW(f.addPassiveFromLandmarks(43, mean, {}, noise), std::invalid_argument);
    EXPECT_THROW(f.addPassiveFromLandmarks(43, mean, {{a, Eigen::MatrixXd::Identity(2, 3)}}, noise),
                 std::invalid_argument);
    EXPECT_ANY_THROW(f.addPassiveFromLandmarks(43, mean, {{12345, Ga}}, noise));
}

}  // namespace
