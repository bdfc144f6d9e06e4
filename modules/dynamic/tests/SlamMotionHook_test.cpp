// SlamMotionHook (thesis Sec. 6.3): no landmark is created from a dynamic cell,
// landmarks on a moved object are flagged and, once unobserved while in view, pruned;
// static ones are left alone. The scene is MotionDetector_test's removed container.
#include "../../dense/tests/synthetic_partition.h"

#include <gtest/gtest.h>
#include <hymm/dense/HybridMetricMap.h>
#include <hymm/dynamic/SlamMotionHook.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <set>
#include <stdexcept>

namespace
{
using namespace hymm::dense::synthetic;
using hymm::dynamic::SlamMotionHook;

/** Returns of a sensor at (1, 7.5) heading +x: the wall x = 17 and, if `box`, the
 *  near face x = 8 of a container over y in [6, 9]. */
hymm::dense::ScanPoints scan(bool box)
{
    hymm::dense::ScanPoints s;
    for (int k = 0; k <= 320; ++k)
    {
        const double th = (-80.0 + 0.5 * k) * M_PI / 180.0;
        const double yw = 7.5 + 16.0 * std::tan(th), yb = 7.5 + 7.0 * std::tan(th);
        double r = 0;
        if (box && yb >= 6.0 && yb <= 9.0)
            r = 7.0 / std::cos(th);
        else if (yw >= 0.0 && yw <= 15.0)
            r = 16.0 / std::cos(th);
        else
            continue;
        s.points.emplace_back(r * std::cos(th), r * std::sin(th));
    }
    return s;
}

void setVehicle(hymm::ekf::EkfSlam& ekf, const Eigen::Vector3d& pose)
{
    // Vehicle plus whichever of the landmarks 1 (on the container's face) and
    // 2 (on the wall) are still in the filter.
    std::vector<std::pair<long, int>> blocks;
    std::vector<Eigen::Vector2d> means;
    if (ekf.hasLandmark(1) || ekf.numLandmarks() == 0)
    {
        blocks.push_back({1, 2});
        means.push_back({8.0, 7.5});
    }
    blocks.push_back({2, 2});
    means.push_back({17.0, 3.0});
    Eigen::VectorXd x(3 + 2 * static_cast<int>(means.size()));
    x.head<3>() = pose;
    for (size_t i = 0; i < means.size(); ++i) x.segment<2>(3 + 2 * static_cast<int>(i)) = means[i];
    ekf.setActiveState(x, 1e-4 * Eigen::MatrixXd::Identity(x.size(), x.size()), blocks);
}

// The occupancy-only map and the slow-motion hook (20 s period, no fast layer) of the
// removed-container tests.
hymm::dense::HybridMetricMap::Options wallMapOptions()
{
    hymm::dense::HybridMetricMap::Options mo;
    mo.enable_points = false;
    mo.occupancy.cell_size_m = 0.2;
    return mo;
}

SlamMotionHook::Options slowHookOptions(bool drop_flagged_observations)
{
    SlamMotionHook::Options o;
    o.enabled = true;
    o.drop_flagged_observations = drop_flagged_observations;
    o.detector.enable_fast = false;
    o.detector.slow_period_s = 20.0;
    return o;
}

TEST(SlamMotionHook, KeepsLandmarksOffAMovedObject)
{
    WallWorld w;
    hymm::dense::HybridMetricMap map(wallMapOptions());
    SlamMotionHook hook(slowHookOptions(false));
    hymm::ekf::EkfSlam ekf{hymm::ekf::EkfSlam::Options{}};
    const Eigen::Vector3d here(1.0, 7.5, 0.0), away(200.0, 200.0, 0.0);
    setVehicle(ekf, here);
    double t = 0;
    hymm::ekf::UpdateReport seen;
    seen.assigned_ids = {1, 2};
    auto pass = [&](bool box) {
        setVehicle(ekf, here);
        for (int k = 0; k < 30; ++k, t += 0.1)
        {
            map.insertScan(scan(box), {1.0, 7.5, 0.0}, w.partition);
            hook.noteUpdate(seen, t);
            EXPECT_TRUE(hook.afterFrame(map, w.partition, ekf, t).empty());
        }
    };
    auto elsewhere = [&](double until) {
        setVehicle(ekf, away);
        for (; t < until; t += 0.1) EXPECT_TRUE(hook.afterFrame(map, w.partition, ekf, t).empty());
    };
    pass(true);
    elsewhere(15.0);
    pass(false);  // the container is gone
    elsewhere(60.0);
    ASSERT_GT(hook.detector().markedCells(hymm::dynamic::MotionKind::Slow), 0u);
    EXPECT_TRUE(hook.flagged().empty());  // landmarks are looked at only near the vehicle
    EXPECT_TRUE(ekf.hasLandmark(1));

    // Creation: an observation of a dynamic cell far from any landmark is dropped, one
    // that will associate with landmark 1 passes, one of the wall passes.
    setVehicle(ekf, here);
    Eigen::Vector2d far_mark(0, 0);
    bool found = false;
    for (double y = 6.0; y <= 9.0 && !found; y += 0.05)
        for (double x = 7.6; x <= 8.4 && !found; x += 0.05)
            if (hook.detector().isDynamic(w.partition, {x, y}) && (Eigen::Vector2d(x, y) - Eigen::Vector2d(8, 7.5)).norm() > 1.2)
            {
                far_mark = {x, y};
                found = true;
            }
    ASSERT_TRUE(found);
    auto obsAt = [&](const Eigen::Vector2d& p, long id) {
        hymm::ekf::RangeBearingObs z;
        const Eigen::Vector2d d = p - here.head<2>();
        z.z = {d.norm(), std::atan2(d.y(), d.x())};
        z.R = 0.01 * Eigen::Matrix2d::Identity();
        z.id = id;
        return z;
    };
    std::vector<size_t> kept;
    const auto passed = hook.filterObservations(
        {obsAt(far_mark, -1), obsAt({8.0, 7.5}, -1), obsAt({17.0, 3.0}, -1), obsAt(far_mark, 7)}, ekf,
        &w.partition, mrpt::poses::CPose3D(), kept);
    ASSERT_EQ(kept.size(), 2u);
    EXPECT_EQ(kept[0], 1u);
    EXPECT_EQ(kept[1], 2u);
    EXPECT_EQ(passed.size(), 2u);
    EXPECT_EQ(hook.stats().creations_blocked, 2u);

    // Back in view: landmark 1 (just observed) is flagged, not pruned; the wall's not.
    hook.noteUpdate(seen, t);
    EXPECT_TRUE(hook.afterFrame(map, w.partition, ekf, t).empty());
    EXPECT_TRUE(hook.flagged().count(1));
    EXPECT_FALSE(hook.flagged().count(2));
    t += 0.1;
    // No longer observed: after prune_unseen_s the flagged landmark
    // leaves the filter, the wall's stays.
    std::vector<long> removed;
    for (int k = 0; k < 60 && removed.empty(); ++k, t += 0.1)
        removed = hook.afterFrame(map, w.partition, ekf, t);
    ASSERT_EQ(removed.size(), 1u);
    EXPECT_EQ(removed[0], 1);
    EXPECT_FALSE(ekf.hasLandmark(1));
    EXPECT_TRUE(ekf.hasLandmark(2));
    EXPECT_EQ(hook.stats().landmarks_pruned, 1u);
}

TEST(SlamMotionHook, DropsObservationsOfFlaggedLandmarksWhenAsked)
{
    // The same removed container; with drop_flagged_observations the landmark on it,
    // once flagged, feeds no update even though something is still seen there.
    WallWorld w;
    hymm::dense::HybridMetricMap map(wallMapOptions());
    SlamMotionHook hook(slowHookOptions(true));
    hymm::ekf::EkfSlam ekf{hymm::ekf::EkfSlam::Options{}};
    const Eigen::Vector3d here(1.0, 7.5, 0.0), away(200.0, 200.0, 0.0);
    double t = 0;
    hymm::ekf::UpdateReport both, wall;
    both.assigned_ids = {1, 2};
    wall.assigned_ids = {2};
    auto visit = [&](bool box, const Eigen::Vector3d& at, double until, const hymm::ekf::UpdateReport* seen) {
        setVehicle(ekf, at);
        for (; t < until; t += 0.1)
        {
            if (at == here) map.insertScan(scan(box), {1.0, 7.5, 0.0}, w.partition);
            if (seen) hook.noteUpdate(*seen, t);
            hook.afterFrame(map, w.partition, ekf, t);
        }
    };
    visit(true, here, 3.0, &both);
    visit(true, away, 15.0, nullptr);
    visit(false, here, 18.0, &both);
    visit(false, away, 60.0, nullptr);
    visit(false, here, 60.05, &both);
    ASSERT_TRUE(hook.flagged().count(1));
    ASSERT_FALSE(hook.flagged().count(2));
    auto obsAt = [&](const Eigen::Vector2d& p, long id) {
        hymm::ekf::RangeBearingObs z;
        const Eigen::Vector2d d = p - here.head<2>();
        z.z = {d.norm(), std::atan2(d.y(), d.x())};
        z.R = 0.01 * Eigen::Matrix2d::Identity();
        z.id = id;
        return z;
    };
    std::vector<size_t> kept;
    hook.filterObservations({obsAt({8.1, 7.4}, -1), obsAt({17.0, 3.0}, -1), obsAt({8.0, 7.5}, 1), obsAt({17.0, 3.0}, 2)},
                            ekf, &w.partition, mrpt::poses::CPose3D(), kept);
    EXPECT_EQ(kept, (std::vector<size_t>{1, 3}));
    EXPECT_EQ(hook.stats().flagged_dropped, 2u);
    // Only the wall is updated from now on: landmark 1 goes after prune_unseen_s.
    std::vector<long> removed;
    for (int k = 0; k < 60 && removed.empty(); ++k, t += 0.1)
    {
        hook.noteUpdate(wall, t);
        removed = hook.afterFrame(map, w.partition, ekf, t);
    }
    EXPECT_EQ(removed, std::vector<long>{1});
    EXPECT_TRUE(ekf.hasLandmark(2));
}

TEST(SlamMotionHook, FlagsExactlyTheLandmarksInViewInADynamicCell)
{
    // afterFrame looks only at landmarks near the regions with marked cells: the set it
    // flags must be the one of the definition, every landmark of the filter in the view
    // box that lies in a dynamic cell. The removed container's slow marks, then a dense
    // grid of landmarks over it and a coarse one over a wider area, the view box's edge
    // (x = 8.1) cutting through the marks.
    WallWorld w;
    hymm::dense::HybridMetricMap map(wallMapOptions());
    auto o = slowHookOptions(false);
    o.prune_flagged = false;
    SlamMotionHook hook(o);
    hymm::ekf::EkfSlam ekf{hymm::ekf::EkfSlam::Options{}};
    const Eigen::Vector3d here(1.0, 7.5, 0.0), away(200.0, 200.0, 0.0);
    double t = 0;
    auto visit = [&](bool box, const Eigen::Vector3d& at, double until) {
        setVehicle(ekf, at);
        for (; t < until; t += 0.1)
        {
            if (at == here) map.insertScan(scan(box), {1.0, 7.5, 0.0}, w.partition);
            hook.afterFrame(map, w.partition, ekf, t);
        }
    };
    visit(true, here, 3.0);
    visit(true, away, 15.0);
    visit(false, here, 18.0);
    visit(false, away, 60.0);
    ASSERT_GT(hook.detector().markedCells(hymm::dynamic::MotionKind::Slow), 0u);

    std::vector<Eigen::Vector2d> pts;
    for (double x = 7.0; x <= 9.2 + 1e-9; x += 0.1)
        for (double y = 5.5; y <= 9.5 + 1e-9; y += 0.1) pts.emplace_back(x, y);
    for (double x = -40.0; x <= 60.0; x += 5.0)
        for (double y = -30.0; y <= 45.0; y += 5.0) pts.emplace_back(x, y);
    const Eigen::Vector3d vehicle(8.1 - o.view_range_m, 7.5, 0.0);
    Eigen::VectorXd x(3 + 2 * static_cast<Eigen::Index>(pts.size()));
    x.head<3>() = vehicle;
    std::vector<std::pair<long, int>> blocks;
    for (size_t i = 0; i < pts.size(); ++i)
    {
        x.segment<2>(3 + 2 * static_cast<Eigen::Index>(i)) = pts[i];
        blocks.push_back({100 + static_cast<long>(i), 2});
    }
    ekf.setActiveState(x, 1e-4 * Eigen::MatrixXd::Identity(x.size(), x.size()), blocks);
    hook.afterFrame(map, w.partition, ekf, t);

    std::set<long> expected;
    size_t dynamic_outside = 0;
    const auto& det = hook.detector();
    for (size_t i = 0; i < pts.size(); ++i)
    {
        const bool dyn = det.isDynamic(w.partition, pts[i]);
        // Either layer, as the two single-layer look-ups.
        EXPECT_EQ(dyn, det.isDynamic(hymm::dynamic::MotionKind::Slow, w.partition, pts[i]) ||
                           det.isDynamic(hymm::dynamic::MotionKind::Fast, w.partition, pts[i]));
        const bool in_box = (pts[i] - vehicle.head<2>()).cwiseAbs().maxCoeff() <= o.view_range_m;
        if (dyn && in_box) expected.insert(100 + static_cast<long>(i));
        if (dyn && !in_box) ++dynamic_outside;
    }
    EXPECT_GE(expected.size(), 3u);
    EXPECT_GE(dynamic_outside, 3u);  // the box's edge does cut the marks
    EXPECT_EQ(hook.flagged(), expected);
}

TEST(SlamMotionHookOptions, ReadsBothSections)
{
    mrpt::config::CConfigFileMemory cfg(
        "[DynamicSlam]\nenabled = true\nprune_unseen_s = 2\n[MotionDetector]\nslow_period_s = 30\n");
    SlamMotionHook::Options o;
    o.loadAll(cfg);
    EXPECT_TRUE(o.enabled);
    EXPECT_DOUBLE_EQ(o.prune_unseen_s, 2.0);
    EXPECT_DOUBLE_EQ(o.detector.slow_period_s, 30.0);
    mrpt::config::CConfigFileMemory typo("[DynamicSlam]\nenable = true\n");
    EXPECT_THROW(o.loadAll(typo), std::invalid_argument);
}

}  // namespace
