#include <gtest/gtest.h>
#include <hymm/ekf/DataAssociation.h>

namespace
{
using namespace hymm::ekf;

/** k candidates in a row along the range axis whose predictions share a common range
 *  error of variance `common` (think: vehicle position error), plus small independent
 *  terms. Observations are the first m predictions shifted by `shift` in range. */
AssociationProblem rowProblem(int k, int m, double common, double shift)
{
    AssociationProblem p;
    p.C = Eigen::MatrixXd::Zero(2 * k, 2 * k);
    for (int a = 0; a < k; ++a)
    {
        p.h.emplace_back(10.0 + a, 0.0);
        for (int b = 0; b < k; ++b) p.C(2 * a, 2 * b) = common;
        p.C(2 * a, 2 * a) += 1e-3;
        p.C(2 * a + 1, 2 * a + 1) = 1e-4;
    }
    for (int i = 0; i < m; ++i)
    {
        p.z.push_back(p.h[static_cast<size_t>(i)] + Eigen::Vector2d(shift, 0.0));
        p.R.push_back(Eigen::Vector2d(0.05 * 0.05, 1e-4).asDiagonal());
    }
    return p;
}

TEST(DataAssociationTest, InnovationWrapsBearing)
{
    const Eigen::Vector2d nu =
        rangeBearingInnovation(Eigen::Vector2d(5.0, 3.1), Eigen::Vector2d(4.0, -3.1));
    EXPECT_NEAR(nu[0], 1.0, 1e-15);
    EXPECT_NEAR(nu[1], 6.2 - 2 * M_PI, 1e-12);
}

TEST(DataAssociationTest, NearestNeighbourPicksClosestAndUsesEachLandmarkOnce)
{
    AssociationProblem p = rowProblem(3, 3, 0.0, 0.0);
    p.z[0] = p.h[1] + Eigen::Vector2d(0.01, 0.0);  // two observations close to candidate 1
    p.z[1] = p.h[1] + Eigen::Vector2d(0.05, 0.0);
    const AssociationResult r = associate(p, AssociationMethod::NearestNeighbour, 0.99);
    EXPECT_EQ(r.assignment, (std::vector<int>{1, -1, 2}));
}

TEST(DataAssociationTest, JcbbSucceedsWhereNearestNeighbourFailsInClutter)
{
    // A common shift of 0.6 m with landmarks 1 m apart: each observation is individually
    // closer to the next landmark (0.4 m) than to its own (0.6 m).
    const AssociationProblem p = rowProblem(4, 4, 1.0, 0.6);
    const AssociationResult nn = associate(p, AssociationMethod::NearestNeighbour, 0.99);
    EXPECT_EQ(nn.assignment, (std::vector<int>{1, 2, 3, -1}));
    const AssociationResult jc = associate(p, AssociationMethod::JCBB, 0.99);
    EXPECT_EQ(jc.assignment, (std::vector<int>{0, 1, 2, 3}));
    EXPECT_LT(jc.joint_nis, 1.0);
    EXPECT_GT(jc.jcbb_nodes, 4u);
    EXPECT_FALSE(jc.jcbb_truncated);
}

TEST(DataAssociationTest, JcbbRejectsIndividuallyCompatibleButJointlyIncompatiblePairs)
{
    AssociationProblem p = rowProblem(2, 2, 1.0, 0.0);
    p.z[0] = p.h[0] + Eigen::Vector2d(1.5, 0.0);   // shift +1.5
    p.z[1] = p.h[1] + Eigen::Vector2d(-1.5, 0.0);  // shift -1.5: not the same vehicle error
    const AssociationResult nn = associate(p, AssociationMethod::NearestNeighbour, 0.99);
    int nn_pairs = 0, jc_pairs = 0;
    for (int a : nn.assignment) nn_pairs += a >= 0;
    const AssociationResult jc = associate(p, AssociationMethod::JCBB, 0.99);
    for (int a : jc.assignment) jc_pairs += a >= 0;
    EXPECT_EQ(nn_pairs, 2);
    EXPECT_EQ(jc_pairs, 1);
}

TEST(DataAssociationTest, JcbbNodeBudgetIsReported)
{
    const AssociationProblem p = rowProblem(8, 8, 1.0, 0.3);
    const AssociationResult r = associate(p, AssociationMethod::JCBB, 0.99, 5);
    EXPECT_TRUE(r.jcbb_truncated);
    EXPECT_LE(r.jcbb_nodes, 5u);
}

TEST(DataAssociationTest, RejectsMalformedProblems)
{
    AssociationProblem p = rowProblem(2, 2, 0.0, 0.0);
    p.R.pop_back();
    EXPECT_THROW(associate(p, AssociationMethod::JCBB, 0.99), std::invalid_argument);
    p = rowProblem(2, 2, 0.0, 0.0);
    EXPECT_THROW(associate(p, AssociationMethod::JCBB, 1.5), std::invalid_argument);
}

}  // namespace
