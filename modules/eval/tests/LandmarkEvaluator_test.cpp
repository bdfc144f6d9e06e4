#include <gtest/gtest.h>
#include <hymm/eval/LandmarkEvaluator.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>

namespace
{
using hymm::io::LandmarkRecord;
using hymm::eval::LandmarkEstimate;
using hymm::eval::LandmarkEvaluator;
using hymm::eval::NeesStatus;
using hymm::eval::Se2Transform;
using Assoc = LandmarkEvaluator::Association;

LandmarkEstimate est(long id, double x, double y)
{
    LandmarkEstimate e;
    e.id = id;
    e.position = {x, y};
    return e;
}

LandmarkEvaluator::Options opts(Assoc a, double gate = 1.0)
{
    LandmarkEvaluator::Options o;
    o.association = a;
    o.gate = gate;
    return o;
}

const std::vector<LandmarkRecord> kTruth = {{1, 0, 0, {}}, {2, 10, 0, {}}, {3, 0, 10, {}}};

TEST(LandmarkEvaluatorTest, AssociatesByIdWhenIdsAreTrueIds)
{
    const auto r = LandmarkEvaluator(opts(Assoc::Auto)).evaluate({est(3, 0, 10.3), est(1, 0.4, 0)}, kTruth);
    EXPECT_EQ(r.used, Assoc::Id);
    ASSERT_EQ(r.matches.size(), 2u);
    EXPECT_EQ(r.matches[0].truth, 2u);
    EXPECT_NEAR(r.matches[0].error, 0.3, 1e-12);
    EXPECT_NEAR(r.mean_error, 0.35, 1e-12);
    EXPECT_NEAR(r.max_error, 0.4, 1e-12);
    EXPECT_NEAR(r.rmse, std::sqrt(0.125), 1e-12);
    EXPECT_EQ(r.unmatched_estimates, 0u);
    EXPECT_EQ(r.unmatched_truth, 1u);
    EXPECT_EQ(r.nees_count, 0u);
    EXPECT_TRUE(std::isnan(r.mean_nees));
}

TEST(LandmarkEvaluatorTest, GreedyNearestNeighbourIsOneToOneWithinTheGate)
{
    const std::vector<LandmarkRecord> truth = {{1, 0, 0, {}}, {2, 1.2, 0, {}}};
    // A-T1 0.1, B-T1 0.5, B-T2 0.7, A-T2 1.1 (outside the gate); C is far from everything.
    const auto r = LandmarkEvaluator(opts(Assoc::Auto, 1.0))
                       .evaluate({est(-1, 0.1, 0), est(-1, 0.5, 0), est(-1, 50, 50)}, truth);
    EXPECT_EQ(r.used, Assoc::Nearest);
    ASSERT_EQ(r.matches.size(), 2u);
    EXPECT_EQ(r.matches[0].estimate, 0u);
    EXPECT_EQ(r.matches[0].truth, 0u);
    EXPECT_NEAR(r.matches[0].error, 0.1, 1e-12);
    EXPECT_EQ(r.matches[1].estimate, 1u);
    EXPECT_EQ(r.matches[1].truth, 1u);
    EXPECT_NEAR(r.matches[1].error, 0.7, 1e-12);
    EXPECT_EQ(r.unmatched_estimates, 1u);
    EXPECT_EQ(r.unmatched_truth, 0u);
}

TEST(LandmarkEvaluatorTest, UnknownOrRepeatedIdsFallBackToNearest)
{
    // ID 7 is not a true ID: auto must not trust the IDs.
    auto r = LandmarkEvaluator(opts(Assoc::Auto)).evaluate({est(1, 0.1, 0), est(7, 10, 0.2)}, kTruth);
    EXPECT_EQ(r.used, Assoc::Nearest);
    EXPECT_EQ(r.matches.size(), 2u);
    r = LandmarkEvaluator(opts(Assoc::Auto)).evaluate({est(1, 0.1, 0), est(1, 10, 0.2)}, kTruth);
    EXPECT_EQ(r.used, Assoc::Nearest);
    // Forced ID association: the repeated ID matches once only.
    r = LandmarkEvaluator(opts(Assoc::Id)).evaluate({est(1, 0.1, 0), est(1, 10, 0.2)}, kTruth);
    EXPECT_EQ(r.matches.size(), 1u);
    EXPECT_EQ(r.unmatched_estimates, 1u);
}

TEST(LandmarkEvaluatorTest, NeesUsesEachCovarianceAndReportsSingularOnes)
{
    auto a = est(1, 0.1, 0.2);
    a.has_cov = true;
    a.cov << 0.01, 0, 0, 0.04;  // NEES = 1 + 1
    auto b = est(2, 10.3, 0);
    b.has_cov = true;
    b.cov << 0.09, 0.09, 0.09, 0.09;  // singular
    const auto r = LandmarkEvaluator(opts(Assoc::Id)).evaluate({a, b}, kTruth);
    ASSERT_EQ(r.matches.size(), 2u);
    EXPECT_TRUE(r.matches[0].has_nees);
    EXPECT_NEAR(r.matches[0].nees.value, 2.0, 1e-12);
    EXPECT_EQ(r.matches[1].nees.status, NeesStatus::Singular);
    EXPECT_EQ(r.nees_count, 1u);
    EXPECT_EQ(r.nees_singular, 1u);
    EXPECT_NEAR(r.mean_nees, 2.0, 1e-12);
}

TEST(LandmarkEvaluatorTest, AlignmentMovesEstimatesAndRotatesCovariances)
{
    const Se2Transform T{0, 0, 3.14159265358979323846 / 2};
    // In the estimate's frame (0, -1.1) maps to (1.1, 0): 0.1 m from the truth at (1, 0).
    auto e = est(1, 0, -1.1);
    e.has_cov = true;
    e.cov << 0.04, 0, 0, 0.01;  // becomes diag(0.01, 0.04): NEES = 0.01 / 0.01
    const std::vector<LandmarkRecord> truth = {{1, 1, 0, {}}};
    const auto r = LandmarkEvaluator(opts(Assoc::Id)).evaluate({e}, truth, &T);
    ASSERT_EQ(r.matches.size(), 1u);
    EXPECT_NEAR(r.matches[0].error, 0.1, 1e-12);
    EXPECT_NEAR(r.matches[0].nees.value, 1.0, 1e-9);
}

TEST(LandmarkEvaluatorTest, EstimatesFromRecordsReadCovarianceColumns)
{
    const std::vector<LandmarkRecord> recs = {{4, 1, 2, {0.5, 0.01, 0.002, 0.03}}};
    const auto e = hymm::eval::landmarkEstimatesFromRecords(recs, 1);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_TRUE(e[0].has_cov);
    EXPECT_DOUBLE_EQ(e[0].cov(0, 0), 0.01);
    EXPECT_DOUBLE_EQ(e[0].cov(0, 1), 0.002);
    EXPECT_DOUBLE_EQ(e[0].cov(1, 0), 0.002);
    EXPECT_DOUBLE_EQ(e[0].cov(1, 1), 0.03);
    EXPECT_FALSE(hymm::eval::landmarkEstimatesFromRecords(recs)[0].has_cov);
    EXPECT_THROW(hymm::eval::landmarkEstimatesFromRecords(recs, 2), std::invalid_argument);
}

TEST(LandmarkEvaluatorTest, OptionsLoadStrictly)
{
    mrpt::config::CConfigFileMemory cfg("[L]\nassociation = nearest\ngate = 3\n");
    LandmarkEvaluator::Options o;
    o.loadFromConfigFile(cfg, "L");
    EXPECT_EQ(o.association, Assoc::Nearest);
    EXPECT_DOUBLE_EQ(o.gate, 3.0);
    mrpt::config::CConfigFileMemory bad("[L]\ngate = 0\n");
    EXPECT_THROW(LandmarkEvaluator::Options().loadFromConfigFile(bad, "L"), std::invalid_argument);
    mrpt::config::CConfigFileMemory typo("[L]\ngating = 1\n");
    EXPECT_THROW(LandmarkEvaluator::Options().loadFromConfigFile(typo, "L"), std::invalid_argument);
}

}  // namespace
