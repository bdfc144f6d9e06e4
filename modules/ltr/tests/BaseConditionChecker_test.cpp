/**
 * @file BaseConditionChecker_test.cpp
 * @brief Each Sec. 3.5 condition accepts a good case and rejects a bad one with the
 *        right reason; strict options loading.
 */
#include "hymm/ltr/BaseConditionChecker.h"

#include "synthetic_map.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <stdexcept>

namespace
{
using namespace hymm::ltr;
using V2 = Eigen::Vector2d;

const std::vector<V2> kGood{V2(0, 0), V2(10, 0), V2(4, 9)};

BaseConditionChecker defaultChecker() { return BaseConditionChecker(BaseConditionChecker::Options()); }

TEST(BaseConditionCheckerTest, WellCorrelatedWellShapedTriangleIsAccepted)
{
    const auto view = synthetic::makeSyntheticView(kGood, Eigen::Vector3d(4, 3, 0));
    const CheckResult r = defaultChecker().check({100, 101, 102}, view, {});
    EXPECT_TRUE(r.accepted()) << toString(r.reason) << ": " << r.detail;
}

TEST(BaseConditionCheckerTest, WeakVertexCorrelationIsRejected)
{
    // Small common error, large independent errors: vertices nearly uncorrelated.
    synthetic::SyntheticNoise noise;
    noise.sigma_common = 0.2;
    noise.sigma_0 = 0.5;
    noise.growth = 0;
    noise.sigma_vehicle = 0.01;
    const auto view = synthetic::makeSyntheticView(kGood, Eigen::Vector3d(4, 3, 0), noise);
    const CheckResult r = defaultChecker().checkCorrelation({100, 101, 102}, view);
    EXPECT_EQ(r.reason, BaseCondition::LowVertexCorrelation) << r.detail;
    EXPECT_NEAR(r.value, 0.04 / (0.04 + 0.25), 1e-9);  // identical diagonal blocks
}

TEST(BaseConditionCheckerTest, WeakVehicleCorrelationIsRejected)
{
    // Vertices correlated with each other but a vehicle with a large own error.
    synthetic::SyntheticNoise noise;
    noise.sigma_vehicle = 2.0;
    const auto view = synthetic::makeSyntheticView(kGood, Eigen::Vector3d(4, 3, 0), noise);
    const auto checker = defaultChecker();
    const CheckResult r = checker.checkCorrelation({100, 101, 102}, view);
    EXPECT_EQ(r.reason, BaseCondition::LowVehicleCorrelation) << r.detail;
    EXPECT_LT(r.value, 0.9);
    // Switching the vehicle condition off accepts the same triangle.
    BaseConditionChecker::Options o;
    o.min_vehicle_correlation = 0;
    EXPECT_TRUE(BaseConditionChecker(o).checkCorrelation({100, 101, 102}, view).accepted());
}

TEST(BaseConditionCheckerTest, CorrelationCoefficientDefinitions)
{
    const Eigen::Matrix2d a = (Eigen::Matrix2d() << 2, 0.5, 0.5, 1).finished();
    using CM = CorrelationMeasure;
    // Identical variables: 1; independent: 0.
    EXPECT_NEAR(BaseConditionChecker::correlationCoefficient(a, a, a, CM::MinCanonical), 1, 1e-9);
    EXPECT_NEAR(
        BaseConditionChecker::correlationCoefficient(a, Eigen::Matrix2d::Zero(), a, CM::MinCanonical),
        0, 1e-12);
    // Invariant to a rotation of one block (the per-axis form is not).
    const double th = 0.7;
    const Eigen::Matrix2d r = (Eigen::Matrix2d() << std::cos(th), -std::sin(th), std::sin(th), std::cos(th)).finished();
    const Eigen::Matrix2d pab = 0.8 * a;
    const Eigen::Matrix2d pbb = a;
    const double c0 = BaseConditionChecker::correlationCoefficient(a, pab, pbb, CM::MinCanonical);
    const double c1 = BaseConditionChecker::correlationCoefficient(
        a, pab * r.transpose(), r * pbb * r.transpose(), CM::MinCanonical);
    EXPECT_NEAR(c0, 0.8, 1e-9);
    EXPECT_NEAR(c0, c1, 1e-9);
    // Per axis (Eq. 2.62): min_k |P_ab(k,k)| / sqrt(P_aa(k,k) P_bb(k,k)).
    const Eigen::Matrix2d pab2 = (Eigen::Matrix2d() << 1.0, 0, 0, 0.3).finished();
    EXPECT_NEAR(
        BaseConditionChecker::correlationCoefficient(a, pab2, a, CM::PerAxis),
        std::min(1.0 / 2.0, 0.3 / 1.0), 1e-12);
    // Vehicle with an exactly known heading: rank-deficient block is handled.
    Eigen::Matrix3d pvv = Eigen::Matrix3d::Zero();
    pvv.topLeftCorner<2, 2>() = a;
    Eigen::Matrix<double, 2, 3> plv = Eigen::Matrix<double, 2, 3>::Zero();
    plv.leftCols<2>() = a;
    EXPECT_NEAR(BaseConditionChecker::correlationCoefficient(a, plv, pvv, CM::MinCanonical), 1, 1e-9);
    // A perfectly known block cannot deform anything: coefficient 1, never NaN.
    EXPECT_EQ(
        BaseConditionChecker::correlationCoefficient(
            Eigen::Matrix2d::Zero(), Eigen::Matrix2d::Zero(), a, CM::MinCanonical),
        1.0);
}

TEST(BaseConditionCheckerTest, GeometryConditions)
{
    const auto checker = defaultChecker();
    const Eigen::Matrix2d small = 0.01 * Eigen::Matrix2d::Identity();
    const std::array<Eigen::Matrix2d, 3> c{small, small, small};
    EXPECT_TRUE(checker.checkGeometry({kGood[0], kGood[1], kGood[2]}, c).accepted());
    // Collinear / tiny.
    EXPECT_EQ(checker.checkGeometry({V2(0, 0), V2(10, 0), V2(5, 0)}, c).reason, BaseCondition::SmallArea);
    // Thin: 3 degree angle at the first vertex.
    EXPECT_EQ(
        checker.checkGeometry({V2(0, 0), V2(40, 0), V2(40, 2)}, c).reason, BaseCondition::SmallAngle);
    // Long edge.
    EXPECT_EQ(
        checker.checkGeometry({V2(0, 0), V2(60, 0), V2(30, 40)}, c).reason, BaseCondition::LongEdge);
    // Fig. 3.10a: vertex 2 is 3 m from the opposite edge; a 3-sigma ellipse of 1.5 m
    // sigma across that edge reaches it, one along the edge does not.
    const TriangleFrame::Vertices flat{V2(0, 0), V2(10, 0), V2(5, 3)};
    std::array<Eigen::Matrix2d, 3> cy = c, cx = c;
    cy[2] = Eigen::Vector2d(0.01, 2.25).asDiagonal();
    cx[2] = Eigen::Vector2d(2.25, 0.01).asDiagonal();
    const CheckResult bad = checker.checkGeometry(flat, cy);
    EXPECT_EQ(bad.reason, BaseCondition::IllConditioned) << bad.detail;
    EXPECT_NEAR(bad.value, 4.5, 1e-9);
    EXPECT_NEAR(bad.limit, 3.0, 1e-9);
    EXPECT_TRUE(checker.checkGeometry(flat, cx).accepted()) << checker.checkGeometry(flat, cx).detail;
}

TEST(BaseConditionCheckerTest, OverlapAllowsSharedEdgesAndVertices)
{
    const auto checker = defaultChecker();
    const TriangleFrame::Vertices t{V2(0, 0), V2(10, 0), V2(0, 10)};
    const TriangleFrame::Vertices shares_edge{V2(10, 0), V2(10, 10), V2(0, 10)};
    const TriangleFrame::Vertices shares_vertex{V2(10, 0), V2(20, 0), V2(15, 8)};
    const TriangleFrame::Vertices crossing{V2(4, 4), V2(14, 4), V2(9, 12)};
    const TriangleFrame::Vertices inside{V2(1, 1), V2(3, 1), V2(1, 3)};
    EXPECT_TRUE(checker.checkOverlap(shares_edge, {t}).accepted());
    EXPECT_TRUE(checker.checkOverlap(shares_vertex, {t, shares_edge}).accepted());
    EXPECT_EQ(checker.checkOverlap(crossing, {shares_vertex, t}).reason, BaseCondition::Overlap);
    EXPECT_EQ(checker.checkOverlap(inside, {t}).reason, BaseCondition::Overlap);
    EXPECT_EQ(checker.checkOverlap(t, {t}).reason, BaseCondition::Overlap);
    EXPECT_FALSE(BaseConditionChecker::interiorsOverlap(t, {V2(20, 20), V2(30, 20), V2(20, 30)}));
}

TEST(BaseConditionCheckerTest, CheckReportsIdsProblemsFirst)
{
    const auto view = synthetic::makeSyntheticView(kGood, Eigen::Vector3d(4, 3, 0));
    const auto checker = defaultChecker();
    EXPECT_EQ(checker.check({100, 101, 7}, view, {}).reason, BaseCondition::UnknownLandmark);
    EXPECT_EQ(checker.check({100, 101, 101}, view, {}).reason, BaseCondition::RepeatedLandmark);
    const TriangleFrame::Vertices existing{V2(2, 1), V2(8, 1), V2(5, 5)};
    EXPECT_EQ(checker.check({100, 101, 102}, view, {existing}).reason, BaseCondition::Overlap);
    EXPECT_STREQ(toString(BaseCondition::IllConditioned), "IllConditioned");
}

TEST(BaseConditionCheckerTest, OptionsLoadStrictlyFromLtrPartitionSection)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("LtrPartition", "min_vertex_correlation", 0.8);
    cfg.write("LtrPartition", "min_angle_deg", 20.0);
    cfg.write("LtrPartition", "correlation_measure", std::string("per_axis"));
    BaseConditionChecker::Options o;
    o.loadFromConfigFile(cfg, "LtrPartition");
    EXPECT_DOUBLE_EQ(o.min_vertex_correlation, 0.8);
    EXPECT_NEAR(o.min_angle, 20.0 * M_PI / 180.0, 1e-12);
    EXPECT_EQ(o.correlation_measure, CorrelationMeasure::PerAxis);
    EXPECT_DOUBLE_EQ(o.ellipse_sigma, 3.0);  // default kept

    mrpt::config::CConfigFileMemory saved;
    o.saveToConfigFile(saved, "LtrPartition");
    BaseConditionChecker::Options o2;
    o2.loadFromConfigFile(saved, "LtrPartition");
    EXPECT_DOUBLE_EQ(o2.min_vertex_correlation, o.min_vertex_correlation);
    EXPECT_NEAR(o2.min_angle, o.min_angle, 1e-12);
    EXPECT_EQ(o2.correlation_measure, o.correlation_measure);

    mrpt::config::CConfigFileMemory typo;
    typo.write("LtrPartition", "min_vertex_corelation", 0.8);
    EXPECT_THROW(BaseConditionChecker::Options().loadFromConfigFile(typo, "LtrPartition"), std::exception);
    mrpt::config::CConfigFileMemory range;
    range.write("LtrPartition", "min_vertex_correlation", 1.5);
    EXPECT_THROW(BaseConditionChecker::Options().loadFromConfigFile(range, "LtrPartition"), std::exception);
    mrpt::config::CConfigFileMemory measure;
    measure.write("LtrPartition", "correlation_measure", std::string("pearson"));
    EXPECT_THROW(BaseConditionChecker::Options().loadFromConfigFile(measure, "LtrPartition"), std::exception);
}

}  // namespace
