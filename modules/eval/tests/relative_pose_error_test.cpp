#include <gtest/gtest.h>
#include <hymm/eval/relative_pose_error.h>

#include <cmath>
#include <limits>

namespace
{
using hymm::eval::relativePoseError;
using hymm::io::StampedPose2D;

TEST(RelativePoseErrorTest, MatchesHandComputedValuesAndIgnoresARigidMotion)
{
    // Truth: 1 m forward, then a quarter turn in place, then 1 m along the new heading.
    const std::vector<StampedPose2D> truth{{0, 0, 0, 0}, {1, 1, 0, 0}, {2, 1, 0, M_PI / 2}, {3, 1, 1, M_PI / 2}};
    // The same motions seen from another frame (rotated by 0.7 rad and moved): no error.
    std::vector<StampedPose2D> moved;
    for (const auto& p : truth)
    {
        const double c = std::cos(0.7), s = std::sin(0.7);
        moved.push_back({p.t, 5 + c * p.x - s * p.y, -2 + s * p.x + c * p.y, p.phi + 0.7});
    }
    const auto zero = relativePoseError(moved, truth);
    EXPECT_EQ(zero.pairs, 3u);
    EXPECT_NEAR(zero.translation_max, 0, 1e-12);
    EXPECT_NEAR(zero.rotation_max, 0, 1e-12);

    // Estimate: the first step 1.2 m, the turn 0.1 rad short (pi/2 - 0.1), the last
    // step 1 m along the estimated heading. Relative errors: 0.2 m / 0; 0 / 0.1 rad; and
    // the last step is 1 m forward in both frames of their own first sample: 0 / 0.
    const std::vector<StampedPose2D> est{{0, 0, 0, 0},
                                         {1, 1.2, 0, 0},
                                         {2, 1.2, 0, M_PI / 2 - 0.1},
                                         {3, 1.2 + std::cos(M_PI / 2 - 0.1), std::sin(M_PI / 2 - 0.1), M_PI / 2 - 0.1}};
    const auto r = relativePoseError(est, truth);
    EXPECT_NEAR(r.translation_mean, 0.2 / 3, 1e-12);
    EXPECT_NEAR(r.translation_median, 0, 1e-12);
    EXPECT_NEAR(r.translation_max, 0.2, 1e-12);
    EXPECT_NEAR(r.rotation_mean, 0.1 / 3, 1e-12);
    EXPECT_NEAR(r.rotation_max, 0.1, 1e-12);
}

TEST(RelativePoseErrorTest, WrapsHeadingsAcrossPi)
{
    const std::vector<StampedPose2D> truth{{0, 0, 0, M_PI - 0.05}, {1, 0, 0, -M_PI + 0.05}};  // +0.1 rad
    const std::vector<StampedPose2D> est{{0, 0, 0, -M_PI + 0.05}, {1, 0, 0, -M_PI + 0.1}};   // +0.05 rad
    EXPECT_NEAR(relativePoseError(est, truth).rotation_max, 0.05, 1e-12);
    // Relative headings on either side of pi: 3.1 against -3.1 rad is 0.083 rad apart.
    const std::vector<StampedPose2D> t2{{0, 0, 0, 0}, {1, 0, 0, -3.1}};
    const std::vector<StampedPose2D> e2{{0, 0, 0, 0}, {1, 0, 0, 3.1}};
    EXPECT_NEAR(relativePoseError(e2, t2).rotation_max, 2 * M_PI - 6.2, 1e-12);
}

TEST(RelativePoseErrorTest, BadInputThrowsAndOneSampleHasNoPairs)
{
    const std::vector<StampedPose2D> one{{0, 0, 0, 0}};
    const std::vector<StampedPose2D> two{{0, 0, 0, 0}, {1, 1, 0, 0}};
    EXPECT_THROW(relativePoseError(one, two), std::invalid_argument);
    const std::vector<StampedPose2D> nan{{0, 0, 0, 0}, {1, std::numeric_limits<double>::quiet_NaN(), 0, 0}};
    EXPECT_THROW(relativePoseError(nan, two), std::invalid_argument);
    const auto r = relativePoseError(one, one);
    EXPECT_EQ(r.pairs, 0u);
    EXPECT_TRUE(std::isnan(r.translation_mean));
}

}  // namespace
