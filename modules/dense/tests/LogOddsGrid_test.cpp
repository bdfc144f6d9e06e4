/**
 * @file LogOddsGrid_test.cpp
 * @brief The corrected Eq. 4.7 log-odds update against hand-computed values.
 */
#include "hymm/dense/LogOddsGrid.h"
#include "hymm/dense/OccupancyLayer.h"

#include <gtest/gtest.h>

#include <set>
#include <sstream>

namespace
{
using namespace hymm::dense;
using V2 = Eigen::Vector2d;

// Hand values: log(0.7/0.3), log(0.4/0.6), log(0.97/0.03).
constexpr double kHit = 0.8472978603872037;
constexpr double kMiss = -0.4054651081081644;
constexpr double kClamp = 3.4760986898352733;

struct Model
{
    OccupancyLayer::Options o;
    void apply(LogOddsGrid& g) const
    {
        g.applyMarks(o.missIncrement(), o.hitIncrement(), o.clampMinLogOdds(), o.clampMaxLogOdds());
    }
};

/** One beam along the row y = 0.5 of a 10 x 1 grid of 1 m cells, return in cell 5. */
void beam(LogOddsGrid& g)
{
    g.markFree(V2(0.5, 0.5), V2(5.5, 0.5), true);
    g.markOccupied(V2(5.5, 0.5));
}

TEST(LogOddsGridTest, HitAndMissIncrementsMatchHandValues)
{
    const Model m;
    EXPECT_NEAR(m.o.hitIncrement(), kHit, 1e-6);
    EXPECT_NEAR(m.o.missIncrement(), kMiss, 1e-6);
    LogOddsGrid g(V2(0, 0), 10, 1, 1.0, 0.0f);
    beam(g);
    m.apply(g);
    for (int i = 0; i < 5; ++i) EXPECT_NEAR(g.logOdds(i, 0), kMiss, 1e-6) << i;
    EXPECT_NEAR(g.logOdds(5, 0), kHit, 1e-6);
    for (int i = 6; i < 10; ++i) EXPECT_EQ(g.logOdds(i, 0), 0.0f) << "beyond the return";
    EXPECT_NEAR(logistic(g.logOdds(5, 0)), 0.7, 1e-6);
    EXPECT_EQ(g.changedCells(), 6u);
}

TEST(LogOddsGridTest, UpdatesAccumulateAndClamp)
{
    const Model m;
    LogOddsGrid g(V2(0, 0), 10, 1, 1.0, 0.0f);
    for (int k = 0; k < 4; ++k)
    {
        beam(g);
        m.apply(g);
    }
    EXPECT_NEAR(g.logOdds(5, 0), 4 * kHit, 1e-5);  // 3.389 < clamp 3.476
    EXPECT_NEAR(g.logOdds(0, 0), 4 * kMiss, 1e-5);
    beam(g);
    m.apply(g);
    EXPECT_NEAR(g.logOdds(5, 0), kClamp, 1e-5);  // 5 * 0.847 = 4.236 clamped
    for (int k = 0; k < 5; ++k)
    {
        beam(g);
        m.apply(g);
    }
    EXPECT_NEAR(g.logOdds(0, 0), -kClamp, 1e-5);  // 10 * -0.405 = -4.05 clamped at logit(0.03)
}

TEST(LogOddsGridTest, OneHitOnNonUniformPriorGivesTheInverseModel)
{
    // Corrected Eq. 4.7: l = l_prior + logit(P(C|r)) - l_prior = logit(P(C|r)). The printed
    // form (history term repeated) would give 2 logit(0.3) + logit(0.7) - logit(0.3) instead.
    Model m;
    m.o.prob_prior = 0.3;
    m.o.prob_miss = 0.2;
    LogOddsGrid g(V2(0, 0), 10, 1, 1.0, m.o.priorLogOdds());
    beam(g);
    m.apply(g);
    EXPECT_NEAR(logistic(g.logOdds(5, 0)), 0.7, 1e-6);
    EXPECT_NEAR(logistic(g.logOdds(0, 0)), 0.2, 1e-6);
    EXPECT_NEAR(logistic(g.logOdds(9, 0)), 0.3, 1e-6);
    beam(g);
    m.apply(g);
    // Second hit: logit(0.7) + logit(0.7) - logit(0.3) -> P = 0.7^2 / (0.7^2 + 0.3^2 * 0.3 / 0.7)
    const double l2 = 2 * logit(0.7) - logit(0.3);
    EXPECT_NEAR(g.logOdds(5, 0), l2, 1e-5);
}

TEST(LogOddsGridTest, EachCellChangesOncePerScanAndOccupiedWins)
{
    const Model m;
    LogOddsGrid g(V2(0, 0), 10, 2, 1.0, 0.0f);
    beam(g);
    beam(g);                                          // same beam twice in one scan
    g.markFree(V2(0.5, 0.5), V2(8.5, 0.5), false);  // a neighbour passing through cell 5
    m.apply(g);
    EXPECT_NEAR(g.logOdds(2, 0), kMiss, 1e-6);
    EXPECT_NEAR(g.logOdds(5, 0), kHit, 1e-6);
    EXPECT_NEAR(g.logOdds(7, 0), kMiss, 1e-6);
    EXPECT_EQ(g.logOdds(9, 0), 0.0f);
}

TEST(LogOddsGridTest, DiagonalTraversalIsConnectedAndSkipsFrozenCells)
{
    LogOddsGrid g(V2(0, 0), 5, 5, 1.0, 0.0f);
    g.setUpdatable(2, 1, false);
    g.markFree(V2(0.5, 0.2), V2(4.5, 2.9), false);
    g.applyMarks(-1.0f, 1.0f, -5.0f, 5.0f);
    std::set<std::pair<int, int>> visited;
    for (int ix = 0; ix < 5; ++ix)
        for (int iy = 0; iy < 5; ++iy)
            if (g.logOdds(ix, iy) != 0.0f) visited.insert({ix, iy});
    // Line y = 0.2 + 0.675 (x - 0.5): crosses y = 1 at x = 1.685, y = 2 at x = 3.167.
    const std::set<std::pair<int, int>> expected{{0, 0}, {1, 0}, {1, 1}, {3, 1}, {3, 2}, {4, 2}};
    EXPECT_EQ(visited, expected);  // (2, 1) is crossed but frozen
}

TEST(LogOddsGridTest, SaveLoadRoundTripIsExact)
{
    LogOddsGrid g(V2(-1.25, 3.5), 4, 3, 0.3, 0.1f);
    g.setUpdatable(1, 1, false);
    g.markFree(V2(-1.2, 3.6), V2(-0.1, 4.1), true);
    g.markOccupied(V2(-0.1, 4.1));
    g.applyMarks(-0.123456789f, 0.987654321f, -3.0f, 3.0f);
    std::stringstream ss;
    g.save(ss);
    const LogOddsGrid h = LogOddsGrid::load(ss);
    ASSERT_EQ(h.sizeX(), 4);
    ASSERT_EQ(h.sizeY(), 3);
    EXPECT_EQ(h.origin(), g.origin());
    EXPECT_EQ(h.cellSize(), g.cellSize());
    for (int ix = 0; ix < 4; ++ix)
        for (int iy = 0; iy < 3; ++iy)
        {
            EXPECT_EQ(h.logOdds(ix, iy), g.logOdds(ix, iy));
            EXPECT_EQ(h.updatable(ix, iy), g.updatable(ix, iy));
        }
    std::stringstream bad("grid 0x1p+0 nonsense");
    EXPECT_THROW(LogOddsGrid::load(bad), std::runtime_error);
}

}  // namespace
