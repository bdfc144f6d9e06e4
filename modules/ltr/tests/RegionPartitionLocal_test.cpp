/**
 * @file RegionPartitionLocal_test.cpp
 * @brief The per-step O(area) path of the partition: LandmarkCovarianceView::idsNear,
 *        RegionPartition::refreshNear / updateNear / regionsWithMissingLandmarksNear,
 *        against the exact full-map versions.
 */
#include "hymm/ltr/RegionPartition.h"

#include "synthetic_map.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>

namespace
{
using namespace hymm::ltr;
using V2 = Eigen::Vector2d;

/** 14 x 6 landmarks on an 8 m grid, jittered by up to 1.5 m (as RegionPartition_test). */
std::vector<V2> landmarkField()
{
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> j(-1.5, 1.5);
    std::vector<V2> out;
    for (int i = 0; i < 14; ++i)
        for (int k = 0; k < 6; ++k) out.emplace_back(8.0 * i + j(rng), 8.0 * k + j(rng));
    return out;
}

/** Same field, every landmark moved a little (a filter update), one strip more. */
std::vector<V2> corrected(const std::vector<V2>& lms)
{
    std::vector<V2> out;
    for (const V2& p : lms) out.push_back(p + V2(0.02 * std::sin(p.x()), 0.03 * std::cos(p.y())) +
                                          (p.x() < 30 ? V2(0.8, -0.6) : V2(0, 0)));
    return out;
}

/** Partition grown with update() along y = 20 from x = 0 to `x_end`. */
std::unique_ptr<RegionPartition> grown(const std::vector<V2>& lms, double x_end, bool near)
{
    auto p = std::make_unique<RegionPartition>(RegionPartition::Options());
    for (int s = 0; 2.0 * s <= x_end; ++s)
    {
        const auto view = synthetic::makeSyntheticView(lms, Eigen::Vector3d(2.0 * s, 20, 0));
        near ? p->updateNear(view, s) : p->update(view, s);
    }
    return p;
}

TEST(LandmarkCovarianceViewTest, IdsNearEqualsTheBruteForceFilter)
{
    const auto view = synthetic::makeSyntheticView(landmarkField(), Eigen::Vector3d(50, 20, 0));
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(-20, 130), uy(-20, 60), ur(0, 40);
    size_t found = 0;
    for (int k = 0; k < 200; ++k)
    {
        const V2 c(ux(rng), uy(rng));
        const double r = ur(rng);
        std::vector<long> brute;
        for (const long id : view.ids())
            if ((view.mean(id) - c).norm() <= r) brute.push_back(id);
        ASSERT_EQ(view.idsNear(c, r), brute) << c.transpose() << " r " << r;
        // The default implementation (base class) gives the same list.
        ASSERT_EQ(view.LandmarkCovarianceView::idsNear(c, r), brute);
        found += brute.size();
    }
    EXPECT_GT(found, 500u);
    // A landmark exactly on the circle counts.
    const V2 p = view.mean(130);
    const std::vector<long> on = view.idsNear(p + V2(3, 4), 5.0);
    EXPECT_NE(std::find(on.begin(), on.end(), 130L), on.end());
}

TEST(RegionPartitionLocalTest, UpdateNearCreatesTheSameRegionsAsUpdate)
{
    const std::vector<V2> lms = landmarkField();
    RegionPartition full{RegionPartition::Options()};
    RegionPartition near{RegionPartition::Options()};
    size_t created = 0;
    for (int s = 0; s <= 52; ++s)
    {
        // The map is corrected a little every step, as a filter does.
        std::vector<V2> now = lms;
        for (V2& p : now) p += 0.01 * s * V2(std::sin(0.1 * p.x()), std::cos(0.1 * p.y()));
        const auto view = synthetic::makeSyntheticView(now, Eigen::Vector3d(2.0 * s, 20, 0));
        const std::vector<long> a = full.update(view, s);
        const std::vector<long> b = near.updateNear(view, s, 25.0);
        ASSERT_EQ(a, b) << "step " << s;
        for (const long id : a)
        {
            EXPECT_EQ(full.region(id).vertex_ids, near.region(id).vertex_ids);
            for (size_t k = 0; k < 3; ++k)
            {
                EXPECT_EQ(full.region(id).reference[k], near.region(id).reference[k]);
                EXPECT_EQ(full.region(id).current[k], near.region(id).current[k]);
            }
        }
        created += a.size();
    }
    EXPECT_GT(created, 60u);
    EXPECT_EQ(full.size(), near.size());
}

TEST(RegionPartitionLocalTest, RefreshNearUpdatesTheWindowOnlyAndFullRefreshCatchesUp)
{
    const std::vector<V2> lms = landmarkField();
    auto lazy = grown(lms, 104, false);
    auto exact = grown(lms, 104, false);
    ASSERT_GT(lazy->size(), 60u);
    const std::vector<V2> moved = corrected(lms);
    const auto view = synthetic::makeSyntheticView(moved, Eigen::Vector3d(80, 20, 0));
    exact->updateVertexPositions(view);

    // Window around (80, 20): refreshed regions equal the exact ones, the others keep
    // their old vertices.
    const V2 centre(80, 20);
    const double radius = 15;
    const std::vector<long> in_window = lazy->regionsInBox(centre - V2(radius, radius), centre + V2(radius, radius));
    ASSERT_FALSE(in_window.empty());
    std::vector<TriangleFrame::Vertices> before;
    for (const long id : lazy->regionIds()) before.push_back(lazy->region(id).current);
    lazy->refreshNear(view, centre, radius);
    size_t kept = 0;
    size_t k = 0;
    for (const long id : lazy->regionIds())
    {
        const bool refreshed = std::find(in_window.begin(), in_window.end(), id) != in_window.end();
        for (size_t v = 0; v < 3; ++v)
        {
            if (refreshed)
                EXPECT_EQ(lazy->region(id).current[v], exact->region(id).current[v]) << id;
            else
                EXPECT_EQ(lazy->region(id).current[v], before[k][v]) << id;
        }
        if (!refreshed) ++kept;
        ++k;
    }
    EXPECT_GT(kept, 10u);

    // Point lookups inside the window (away from its border) agree with the exact
    // partition already; after a full refresh they agree everywhere.
    std::mt19937 rng(8);
    auto compare = [&](const V2& lo, const V2& hi) {
        std::uniform_real_distribution<double> ux(lo.x(), hi.x()), uy(lo.y(), hi.y());
        int hits = 0;
        for (int s = 0; s < 3000; ++s)
        {
            const V2 p(ux(rng), uy(rng));
            const auto a = lazy->findRegions(p);
            ASSERT_EQ(a, exact->findRegions(p)) << p.transpose();
            hits += !a.empty();
            const V2 q(ux(rng), uy(rng));
            ASSERT_EQ(lazy->regionsInBox(p.cwiseMin(q), p.cwiseMax(q)),
                      exact->regionsInBox(p.cwiseMin(q), p.cwiseMax(q)));
        }
        EXPECT_GT(hits, 500);
    };
    compare(V2(72, 12), V2(88, 28));
    lazy->updateVertexPositions(view);
    compare(V2(-10, -10), V2(115, 50));
    for (const long id : lazy->regionIds())
        for (size_t v = 0; v < 3; ++v)
            EXPECT_EQ(lazy->region(id).current[v], exact->region(id).current[v]);
}

TEST(RegionPartitionLocalTest, MissingLandmarksNearIsTheFullListInsideTheWindow)
{
    const std::vector<V2> lms = landmarkField();
    auto part = grown(lms, 104, true);
    // Drop landmarks 101 (near x = 0) and 170 (near x = 88) from the view.
    std::map<long, int> offsets;
    const auto full_view = synthetic::makeSyntheticView(lms, Eigen::Vector3d(90, 20, 0));
    for (const long id : full_view.ids())
        if (id != 101 && id != 170) offsets[id] = 0;
    // A view without the two landmarks: same means, rebuilt with their ids kept.
    const int n = 3 + 2 * static_cast<int>(offsets.size());
    Eigen::VectorXd mean(n);
    mean.head<3>() = full_view.vehiclePose();
    int o = 3;
    for (auto& [id, off] : offsets)
    {
        off = o;
        mean.segment<2>(o) = full_view.mean(id);
        o += 2;
    }
    const DenseCovarianceView view(mean, Eigen::MatrixXd::Identity(n, n), offsets, 0);

    const std::vector<long> all = part->regionsWithMissingLandmarks(view);
    ASSERT_FALSE(part->regionsUsingLandmark(101).empty());
    ASSERT_FALSE(part->regionsUsingLandmark(170).empty());
    const V2 c(90, 20);
    const double r = 20;
    std::vector<long> expected;
    const std::vector<long> box = part->regionsInBox(c - V2(r, r), c + V2(r, r));
    for (const long id : all)
        if (std::find(box.begin(), box.end(), id) != box.end()) expected.push_back(id);
    EXPECT_EQ(part->regionsWithMissingLandmarksNear(view, c, r), expected);
    EXPECT_EQ(expected, part->regionsUsingLandmark(170));
    EXPECT_GT(all.size(), expected.size());
}

TEST(RegionPartitionLocalTest, OptionsRoundTripAndValidation)
{
    RegionPartition::Options o;
    EXPECT_TRUE(o.local_refresh);
    o.local_refresh = false;
    o.full_refresh_correction_m = 2.5;
    mrpt::config::CConfigFileMemory cfg;
    o.saveToConfigFile(cfg, "LtrPartition");
    RegionPartition::Options r;
    r.loadFromConfigFile(cfg, "LtrPartition");
    EXPECT_FALSE(r.local_refresh);
    EXPECT_DOUBLE_EQ(r.full_refresh_correction_m, 2.5);
    cfg.write("LtrPartition", "full_refresh_correction_m", -1.0);
    EXPECT_THROW(r.loadFromConfigFile(cfg, "LtrPartition"), std::exception);
}

}  // namespace
