/**
 * @file DelayedDenseStoreSim_test.cpp
 * @brief DelayedDenseStore in a simulated frame loop (mini_world.h): UIF keeps the active
 *        EKF bitwise identical, fused returns land where the ground truth is, their
 *        NEES at fusion is chi-square consistent, and the budget holds.
 */
#include "mini_world.h"

#include <hymm/eval/nees.h>
#include <hymm/ltr/TriangleFrame.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

namespace
{
using hymm::uif::DelayedDenseStore;
using hymm::uif::testing::MiniWorld;
using hymm::uif::testing::MiniWorldConfig;

constexpr int kSteps = 45;

MiniWorldConfig config(unsigned seed, bool enabled)
{
    MiniWorldConfig c;
    c.seed = seed;
    c.store.enabled = enabled;
    return c;
}

/** True local coordinates of fused return `fp` in its region's triangle. */
Eigen::Vector2d trueLocal(const MiniWorld& w, const DelayedDenseStore::FusedPoint& fp)
{
    const hymm::ltr::TriangleFrame f(w.landmarks().at(fp.vertex_ids[0]), w.landmarks().at(fp.vertex_ids[1]),
                                     w.landmarks().at(fp.vertex_ids[2]));
    return f.toLocal(w.points().at(static_cast<size_t>(fp.tag)));
}

TEST(DelayedDenseStoreSimTest, ActiveStatesAreBitwiseIdenticalWithAndWithoutTheStore)
{
    MiniWorld with(config(3, true)), without(config(3, false));
    size_t max_blocks = 0;
    for (int k = 0; k < kSteps; ++k)
    {
        with.step();
        without.step();
        max_blocks = std::max(max_blocks, with.ekf().passive().numBlocks());
        ASSERT_EQ(with.ekf().mean().size(), without.ekf().mean().size());
        // Exact equality: the UIF never lets a passive block touch the active states.
        ASSERT_TRUE((with.ekf().mean().array() == without.ekf().mean().array()).all()) << "step " << k;
        ASSERT_TRUE((with.ekf().cov().array() == without.ekf().cov().array()).all()) << "step " << k;
        ASSERT_EQ(with.partition().regionIds(), without.partition().regionIds());
        ASSERT_EQ(without.ekf().passive().numBlocks(), 0u);
        ASSERT_EQ(with.ekf().passive().numBlocks(), with.store().numStoredScans());
    }
    EXPECT_GT(max_blocks, 0u) << "the store never held a scan: the test would prove nothing";
    EXPECT_GT(with.fused().size(), 0u);
    EXPECT_EQ(without.fused().size(), 0u);
    EXPECT_EQ(without.store().numStoredPoints(), 0u);
}

TEST(DelayedDenseStoreSimTest, FusedReturnsLandAtTheGroundTruthInTheRegionLayers)
{
    MiniWorld w(config(5, true));
    for (int k = 0; k < kSteps; ++k) w.step();
    ASSERT_GT(w.fused().size(), 50u);

    size_t in_layers = 0;
    for (const auto& [rid, map] : w.maps()) in_layers += map->layer("points")->size();
    EXPECT_EQ(in_layers, w.fused().size());

    double worst = 0;
    for (const auto& fp : w.fused())
    {
        // Error of the fused position, metric, in the TRUE triangle: local error times D.
        const hymm::ltr::TriangleFrame f(w.landmarks().at(fp.vertex_ids[0]), w.landmarks().at(fp.vertex_ids[1]),
                                         w.landmarks().at(fp.vertex_ids[2]));
        const Eigen::Vector2d err = f.axes() * (fp.local.mean - trueLocal(w, fp));
        worst = std::max(worst, err.norm());
        // The stored reference point is the same local coordinates in the reference triangle.
        const hymm::ltr::TriangleFrame ref(w.partition().region(fp.region_id).reference);
        EXPECT_LT((ref.toLocal(fp.reference) - fp.local.mean).norm(), 1e-6);
    }
    std::printf("fused %zu returns, worst metric error in the true triangle %.3f m\n", w.fused().size(), worst);
    EXPECT_LT(worst, 0.5);
}

TEST(DelayedDenseStoreSimTest, NeesAtFusionIsInsideTheChiSquareBand)
{
    // Per seed, the mean NEES over all fused returns; returns of one run are correlated
    // (shared poses and vertices), so the band of the average over seeds is taken for one
    // 2-dof sample per seed: the mean of correlated chi2(2) variables has mean 2 and a
    // variance no larger than one chi2(2), so this band is conservative, never too tight.
    constexpr int kSeeds = 30;
    std::vector<double> per_seed;
    double sum_all = 0, sum_delay = 0;
    size_t n_all = 0;
    for (int s = 0; s < kSeeds; ++s)
    {
        MiniWorld w(config(100 + static_cast<unsigned>(s), true));
        for (int k = 0; k < kSteps; ++k) w.step();
        ASSERT_GT(w.fused().size(), 20u) << "seed " << s;
        double sum = 0;
        for (const auto& fp : w.fused())
        {
            const Eigen::Vector2d e = fp.local.mean - trueLocal(w, fp);
            const auto v = hymm::eval::nees(e, fp.local.cov);
            ASSERT_TRUE(v.ok());
            sum += v.value;
        }
        for (double d : w.fusionDelays()) sum_delay += d;
        per_seed.push_back(sum / static_cast<double>(w.fused().size()));
        sum_all += sum;
        n_all += w.fused().size();
    }
    double mean = 0;
    for (double v : per_seed) mean += v / kSeeds;
    const auto band = hymm::eval::averageNeesBounds(2, kSeeds, 0.95);
    std::printf("NEES at fusion: mean over %d seeds %.3f (band [%.3f, %.3f]); all %zu returns %.3f; per seed:",
                kSeeds, mean, band.lower, band.upper, n_all, sum_all / static_cast<double>(n_all));
    for (double v : per_seed) std::printf(" %.2f", v);
    std::printf("\nmean delay from observation to fusion: %.2f s\n",
                sum_delay / static_cast<double>(n_all));
    EXPECT_TRUE(band.contains(mean)) << mean;
    // The band is tight enough to reject a covariance off by a factor of 2 either way.
    EXPECT_FALSE(band.contains(2.0 * mean));
    EXPECT_FALSE(band.contains(0.5 * mean));
}

TEST(DelayedDenseStoreSimTest, BudgetIsRespectedAndOldestScansGoFirst)
{
    MiniWorldConfig c = config(7, true);
    c.store.max_stored_points = 120;
    c.store.max_stored_scans = 4;
    MiniWorld w(c);
    size_t evicted = 0;
    for (int k = 0; k < kSteps; ++k)
    {
        w.step();
        const auto& st = w.store();
        ASSERT_LE(st.numStoredPoints(), c.store.max_stored_points);
        ASSERT_LE(st.numStoredScans(), c.store.max_stored_scans);
        ASSERT_EQ(w.ekf().passive().numBlocks(), st.numStoredScans()) << "leaked passive blocks";
        size_t count = 0;
        for (const auto& s : st.scans()) count += s.points.size();
        ASSERT_EQ(count, st.numStoredPoints());
        for (size_t i = 1; i < st.scans().size(); ++i)
            ASSERT_LT(st.scans()[i - 1].scan_id, st.scans()[i].scan_id);
        evicted += w.lastAdd().evicted_scans;
        if (w.lastAdd().scan_id >= 0)
        {
            ASSERT_EQ(st.scans().back().scan_id, w.lastAdd().scan_id);
        }
    }
    EXPECT_GT(evicted, 0u) << "the budget never bound: the test would prove nothing";
}

}  // namespace
