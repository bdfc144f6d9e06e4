#include <gtest/gtest.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>

namespace
{
using hymm::io::StampedPose2D;
using hymm::eval::Se2Transform;
using hymm::eval::TrajectoryEvaluator;
using Assoc = TrajectoryEvaluator::Association;

constexpr double kPi = 3.14159265358979323846;

TrajectoryEvaluator::Options opts(Assoc a, double tol = 0.05, bool align = false)
{
    TrajectoryEvaluator::Options o;
    o.association = a;
    o.time_tolerance = tol;
    o.align = align;
    return o;
}

std::vector<StampedPose2D> curve(size_t n)
{
    std::vector<StampedPose2D> v;
    for (size_t i = 0; i < n; ++i)
    {
        const double t = 0.1 * i;
        v.push_back({t, 5 * std::cos(t), 3 * std::sin(2 * t), std::atan2(std::sin(t), std::cos(t))});
    }
    return v;
}

TEST(TrajectoryEvaluatorTest, ErrorsMatchHandComputedValues)
{
    const std::vector<StampedPose2D> truth = {{0, 0, 0, 0}, {1, 1, 0, 0.1}, {2, 2, 0, 0.2}};
    // Position errors 5 (3-4-5), 0 and 1; heading errors 0.3, 0, -0.1.
    const std::vector<StampedPose2D> est = {{0, 3, 4, 0.3}, {1, 1, 0, 0.1}, {2, 3, 0, 0.1}};
    for (Assoc a : {Assoc::Nearest, Assoc::Interpolate, Assoc::Index})
    {
        const auto r = TrajectoryEvaluator(opts(a)).evaluate(est, truth);
        EXPECT_EQ(r.matched, 3u);
        EXPECT_EQ(r.unmatched, 0u);
        EXPECT_NEAR(r.position_rmse, std::sqrt(26.0 / 3.0), 1e-12);
        EXPECT_NEAR(r.position_mean, 2.0, 1e-12);
        EXPECT_NEAR(r.position_max, 5.0, 1e-12);
        EXPECT_NEAR(r.heading_rmse, std::sqrt((0.09 + 0.01) / 3.0), 1e-12);
        EXPECT_NEAR(r.heading_max, 0.3, 1e-12);
        EXPECT_FALSE(r.aligned);
        ASSERT_EQ(r.errors.size(), 3u);
        EXPECT_NEAR(r.errors[2].dx, 1.0, 1e-12);
        EXPECT_NEAR(r.errors[2].dphi, -0.1, 1e-12);
    }
}

TEST(TrajectoryEvaluatorTest, InterpolatesGroundTruthIncludingHeadingAcrossPi)
{
    const std::vector<StampedPose2D> truth = {{1.0, 1, 2, 3.0}, {0.0, 0, 0, 3.0}, {2.0, 2, 4, -3.0}};
    // Unsorted ground truth; at t = 1.5 the heading is half-way along the short arc through pi.
    const std::vector<StampedPose2D> est = {{0.25, 0.25, 0.5, 3.0}, {1.5, 1.5, 3.0, kPi}};
    const auto r = TrajectoryEvaluator(opts(Assoc::Interpolate, 1.5)).evaluate(est, truth);
    EXPECT_EQ(r.matched, 2u);
    EXPECT_NEAR(r.position_max, 0.0, 1e-12);
    EXPECT_NEAR(r.heading_max, 0.0, 1e-12);
}

TEST(TrajectoryEvaluatorTest, PosesOutsideTheToleranceAreUnmatched)
{
    const std::vector<StampedPose2D> truth = {{0, 0, 0, 0}, {1, 1, 0, 0}, {10, 10, 0, 0}};
    const std::vector<StampedPose2D> est = {
        {0.5, 0.5, 0, 0}, {1.02, 1, 0, 0}, {5, 5, 0, 0}, {10, 10, 0, 0}, {11, 11, 0, 0}};
    const auto nearest = TrajectoryEvaluator(opts(Assoc::Nearest, 0.05)).evaluate(est, truth);
    EXPECT_EQ(nearest.matched, 2u);  // t = 1.02 and t = 10
    EXPECT_EQ(nearest.unmatched, 3u);
    // Interpolation bridges 0..1 (t = 0.5) and hits t = 10 exactly, but neither bridges the
    // 1..10 gap (t = 1.02, 5) nor extrapolates past the end (t = 11).
    const auto interp = TrajectoryEvaluator(opts(Assoc::Interpolate, 2.0)).evaluate(est, truth);
    EXPECT_EQ(interp.matched, 2u);
    EXPECT_NEAR(interp.position_max, 0.0, 1e-12);

    const auto none = TrajectoryEvaluator(opts(Assoc::Nearest)).evaluate(est, {});
    EXPECT_EQ(none.matched, 0u);
    EXPECT_TRUE(std::isnan(none.position_rmse));
}

TEST(TrajectoryEvaluatorTest, IndexAssociationIgnoresTimestamps)
{
    auto truth = curve(20);
    for (auto& p : truth) p.t = 0;  // e.g. a path file without timestamps
    auto est = curve(25);
    const auto r = TrajectoryEvaluator(opts(Assoc::Index)).evaluate(est, truth);
    EXPECT_EQ(r.matched, 20u);
    EXPECT_EQ(r.unmatched, 5u);
    EXPECT_NEAR(r.position_max, 0.0, 1e-12);
}

TEST(TrajectoryEvaluatorTest, AlignmentRecoversAKnownSe2Transform)
{
    const auto truth = curve(40);
    const Se2Transform T{4.0, -1.5, 0.8};
    const Se2Transform inv = T.inverse();
    std::vector<StampedPose2D> est;
    for (const auto& p : truth)
    {
        const Eigen::Vector2d q = inv.apply({p.x, p.y});
        est.push_back({p.t, q.x(), q.y(), inv.applyHeading(p.phi)});
    }
    const auto raw = TrajectoryEvaluator(opts(Assoc::Nearest)).evaluate(est, truth);
    EXPECT_GT(raw.position_rmse, 1.0);
    const auto r = TrajectoryEvaluator(opts(Assoc::Nearest, 0.05, true)).evaluate(est, truth);
    ASSERT_TRUE(r.aligned);
    EXPECT_NEAR(r.alignment.x, 4.0, 1e-9);
    EXPECT_NEAR(r.alignment.y, -1.5, 1e-9);
    EXPECT_NEAR(r.alignment.phi, 0.8, 1e-9);
    EXPECT_NEAR(r.position_max, 0.0, 1e-9);
    EXPECT_NEAR(r.heading_max, 0.0, 1e-9);
}

TEST(TrajectoryEvaluatorTest, OptionsLoadStrictly)
{
    mrpt::config::CConfigFileMemory cfg(
        "[TrajectoryEvaluator]\nassociation = index\ntime_tolerance = 0.2\nalign = true\n");
    TrajectoryEvaluator::Options o;
    o.loadFromConfigFile(cfg, "TrajectoryEvaluator");
    EXPECT_EQ(o.association, Assoc::Index);
    EXPECT_DOUBLE_EQ(o.time_tolerance, 0.2);
    EXPECT_TRUE(o.align);

    mrpt::config::CConfigFileMemory bad("[T]\nassociation = closest\n");
    try
    {
        TrajectoryEvaluator::Options().loadFromConfigFile(bad, "T");
        FAIL() << "no exception";
    }
    catch (const std::invalid_argument& e)
    {
        EXPECT_NE(std::string(e.what()).find("[T] association=closest"), std::string::npos) << e.what();
    }
    mrpt::config::CConfigFileMemory neg("[T]\ntime_tolerance = -1\n");
    EXPECT_THROW(TrajectoryEvaluator::Options().loadFromConfigFile(neg, "T"), std::invalid_argument);
    mrpt::config::CConfigFileMemory typo("[T]\nalign_se2 = true\n");
    EXPECT_THROW(TrajectoryEvaluator::Options().loadFromConfigFile(typo, "T"), std::invalid_argument);
}

}  // namespace
