// Data association inside the filter: NN vs JCBB, ambiguous observations, tentative
// landmark pruning and id allocation.
#include <gtest/gtest.h>
#include <hymm/core/RangeBearingModel.h>
#include <hymm/ekf/EkfSlam.h>

namespace
{
using namespace hymm::ekf;

const mrpt::poses::CPose3D kSensor;  // sensor at the vehicle origin

RangeBearingObs observe(const Eigen::Vector3d& vehicle, const Eigen::Vector2d& lm)
{
    RangeBearingObs o;
    o.z = hymm::core::observeRangeBearing(vehicle, Eigen::Vector3d::Zero(), lm);
    o.R = Eigen::Vector2d(0.02, 0.2 * M_PI / 180.0).cwiseAbs2().asDiagonal();
    return o;
}

/** Landmarks 1 m apart in a row, precisely mapped; the vehicle x is uncertain (1 m). */
EkfSlam rowFilter(AssociationMethod method)
{
    EkfSlam::Options o;
    o.association_method = method;
    EkfSlam f(o);
    Eigen::VectorXd x(3 + 8);
    x << 0, 0, 0, 10, 3, 11, 3, 12, 3, 13, 3;
    Eigen::MatrixXd P = 1e-6 * Eigen::MatrixXd::Identity(11, 11);
    P(0, 0) = 1.0;
    f.setActiveState(x, P, {{10, 2}, {11, 2}, {12, 2}, {13, 2}});
    return f;
}

std::vector<RangeBearingObs> rowObservations()
{
    const Eigen::Vector3d truth(0.6, 0.0, 0.0);  // the vehicle is really 0.6 m ahead
    std::vector<RangeBearingObs> obs;
    for (int k = 0; k < 4; ++k) obs.push_back(observe(truth, Eigen::Vector2d(10.0 + k, 3.0)));
    return obs;
}

TEST(EkfSlamAssociationTest, JcbbFindsTheRightLandmarksWhereNearestNeighbourFails)
{
    EkfSlam nn = rowFilter(AssociationMethod::NearestNeighbour);
    const UpdateReport rn = nn.updateRangeBearing(rowObservations(), kSensor);
    EXPECT_NE(rn.assigned_ids, (std::vector<long>{10, 11, 12, 13}));
    EXPECT_EQ(rn.assigned_ids[1], 10);  // observation of 11 taken for 10

    EkfSlam jc = rowFilter(AssociationMethod::JCBB);
    const UpdateReport rj = jc.updateRangeBearing(rowObservations(), kSensor);
    EXPECT_EQ(rj.assigned_ids, (std::vector<long>{10, 11, 12, 13}));
    EXPECT_EQ(rj.associated, 4u);
    EXPECT_EQ(jc.numLandmarks(), 4u);
    EXPECT_NEAR(jc.vehiclePose()[0], 0.6, 0.05);
}

TEST(EkfSlamAssociationTest, AmbiguousObservationIsDiscardedNotDuplicated)
{
    EkfSlam f{EkfSlam::Options{}};
    Eigen::VectorXd x(5);
    x << 0, 0, 0, 10, 0;
    f.setActiveState(x, 1e-8 * Eigen::MatrixXd::Identity(5, 5), {{0, 2}});
    // R range std 0.1 m: 0.35 m off gives d2 ~ 12.2, between chi2inv(0.99,2) = 9.2 and
    // chi2inv(0.9999,2) = 18.4.
    RangeBearingObs o;
    o.R = Eigen::Vector2d(0.1, 0.01).cwiseAbs2().asDiagonal();
    o.z << 10.35, 0.0;
    RangeBearingObs far = o;
    far.z << 10.0, 0.5;  // 5 m away from the landmark: a new one
    const UpdateReport r = f.updateRangeBearing({o, far}, kSensor);
    EXPECT_EQ(r.ambiguous, 1u);
    EXPECT_EQ(r.created, 1u);
    EXPECT_EQ(r.assigned_ids[0], -1);
    EXPECT_EQ(r.assigned_ids[1], 1);
    EXPECT_EQ(f.numLandmarks(), 2u);
}

TEST(EkfSlamAssociationTest, TentativeLandmarksSeenOnceArePruned)
{
    EkfSlam::Options opt;
    opt.confirm_min_observations = 2;
    opt.confirm_window_steps = 3;
    EkfSlam f(opt);
    f.reset(Eigen::Vector3d::Zero(), 1e-6 * Eigen::Matrix3d::Identity());
    const Eigen::Vector2d real(10, 2), spurious(4, -6);
    const Eigen::Vector3d pose = Eigen::Vector3d::Zero();
    UpdateReport r = f.updateRangeBearing({observe(pose, real), observe(pose, spurious)}, kSensor);
    ASSERT_EQ(r.created, 2u);
    const long real_id = r.assigned_ids[0], spurious_id = r.assigned_ids[1];
    size_t pruned = 0;
    for (int step = 1; step <= 4; ++step)
    {
        r = f.updateRangeBearing({observe(pose, real)}, kSensor);
        EXPECT_EQ(r.assigned_ids[0], real_id);
        pruned += r.pruned;
        if (step < 3)
        {
            EXPECT_TRUE(f.hasLandmark(spurious_id)) << step;
        }
    }
    EXPECT_EQ(pruned, 1u);
    EXPECT_FALSE(f.hasLandmark(spurious_id));
    EXPECT_TRUE(f.hasLandmark(real_id));
    EXPECT_TRUE(f.landmarkBlock(real_id).confirmed);
}

TEST(EkfSlamAssociationTest, KnownIdsCreateAndUpdateAndFreshIdsNeverCollide)
{
    EkfSlam f{EkfSlam::Options{}};
    f.reset(Eigen::Vector3d::Zero(), 1e-6 * Eigen::Matrix3d::Identity());
    RangeBearingObs a = observe(Eigen::Vector3d::Zero(), Eigen::Vector2d(10, 0));
    a.id = 41;
    RangeBearingObs b = observe(Eigen::Vector3d::Zero(), Eigen::Vector2d(0, 12));
    UpdateReport r = f.updateRangeBearing({a, b}, kSensor);
    EXPECT_EQ(r.assigned_ids, (std::vector<long>{41, 42}));
    r = f.updateRangeBearing({a, b}, kSensor);
    EXPECT_EQ(r.associated, 2u);
    EXPECT_EQ(r.assigned_ids, (std::vector<long>{41, 42}));
}

// A known id does not protect against a gross error: with the outlier gate on, a range
// 3 m off (NIS ~ 2e4) is rejected and counted while consistent ones are fused; with the
// gate off (default) the same observation drags the landmark.
TEST(EkfSlamAssociationTest, KnownIdOutlierGateRejectsGrossErrorsOnly)
{
    for (const double gate : {0.0, 0.999})
    {
        EkfSlam::Options o;
        o.known_id_gate_prob = gate;
        EkfSlam f(o);
        f.reset(Eigen::Vector3d::Zero(), 1e-6 * Eigen::Matrix3d::Identity());
        RangeBearingObs good = observe(Eigen::Vector3d::Zero(), Eigen::Vector2d(10, 0));
        good.id = 7;
        f.updateRangeBearing({good}, kSensor);
        UpdateReport r = f.updateRangeBearing({good}, kSensor);
        EXPECT_EQ(r.associated, 1u);
        EXPECT_EQ(r.rejected_gate, 0u);
        RangeBearingObs bad = good;
        bad.z[0] += 3.0;
        r = f.updateRangeBearing({bad}, kSensor);
        const double x = f.landmarkMean(7)[0];
        if (gate > 0.0)
        {
            EXPECT_EQ(r.associated, 0u);
            EXPECT_EQ(r.rejected_gate, 1u);
            EXPECT_NEAR(x, 10.0, 1e-3);
        }
        else
        {
            EXPECT_EQ(r.associated, 1u);
            EXPECT_GT(x, 10.5);
        }
    }
    EkfSlam::Options bad;
    bad.known_id_gate_prob = 1.0;
    EXPECT_THROW(bad.validate(), std::invalid_argument);
}

}  // namespace
