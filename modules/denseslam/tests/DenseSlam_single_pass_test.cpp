/**
 * @file SinglePass_test.cpp
 * @brief The delayed dense store in the whole pipeline on a single pass (thesis Sec.
 *        3.7.3): with the store, the dense map holds what the laser saw before the
 *        regions around it existed; without it, those parts are holes.
 *
 * The shipped scenario configs/sim/ch3_single_pass.ini (a 165 m avenue driven once,
 * objects between the tree rows) is simulated in memory and fed to two DenseSlam
 * pipelines built from configs/ch3_single_pass_slam.ini, store off and on. Both maps
 * are drawn on the true landmarks (eval::pointsAtTrueVertices: the feature map's drift,
 * which the store cannot change, is left out) and compared with the part of the true
 * outlines the laser saw (eval::laserSeenOutline: scans at the true poses).
 */
#include <gtest/gtest.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/eval/laser_coverage.h>
#include <hymm/sim/Simulator.h>
#include <hymm/sim/frame_feed.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

namespace
{
using hymm::denseslam::DenseSlam;
using V2 = Eigen::Vector2d;

std::unique_ptr<DenseSlam> pipeline(bool store)
{
    const std::string path = std::string(HYMM_SOURCE_DIR) + "/configs/ch3_single_pass_slam.ini";
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    if (!in) throw std::runtime_error("cannot read " + path);
    mrpt::config::CConfigFileMemory cfg(text.str());
    cfg.write("DelayedDenseStore", "enabled", store);
    // new with the prvalue: DenseSlam is built in place (it is not movable).
    return std::unique_ptr<DenseSlam>(new DenseSlam(DenseSlam::fromConfig(cfg)));
}

/** The map's points drawn on the true landmarks (the detector reports the true ids). */
std::vector<V2> landmarkFramePoints(const DenseSlam& slam, const hymm::sim::World& world)
{
    std::map<long, V2> truth;
    for (const auto& l : world.landmarks()) truth[l.id] = l.position;
    const auto vertices = hymm::eval::trueRegionVertices(*slam.partition(), truth);
    const auto pts =
        hymm::eval::pointsAtTrueVertices(*slam.hybridMap(), *slam.partition(), vertices);
    EXPECT_EQ(pts.regions_skipped, 0u);
    return pts.points;
}

/** Points of `on` not in `off` (equal in single precision: the points layer stores floats). */
std::vector<V2> fusedPoints(const std::vector<V2>& on, const std::vector<V2>& off)
{
    std::map<std::pair<float, float>, size_t> count;
    for (const V2& p : off) ++count[{static_cast<float>(p.x()), static_cast<float>(p.y())}];
    std::vector<V2> out;
    for (const V2& p : on)
    {
        auto it = count.find({static_cast<float>(p.x()), static_cast<float>(p.y())});
        if (it != count.end() && it->second > 0)
            --it->second;
        else
            out.push_back(p);
    }
    return out;
}

TEST(SinglePassTest, TheStoreMapsWhatTheLaserSawBeforeRegionsExisted)
{
    const auto scenario = hymm::sim::Scenario::fromFile(std::string(HYMM_SOURCE_DIR) +
                                                        "/configs/sim/ch3_single_pass.ini");
    hymm::sim::Simulator sim(scenario);
    auto off = pipeline(false), on = pipeline(true);
    std::vector<hymm::eval::TimedScan> scans;
    std::vector<hymm::io::StampedPose2D> true_path;
    hymm::sim::SimFrame f;
    while (sim.next(f))
    {
        const mrpt::poses::CPosePDFGaussian odo = hymm::sim::odometryIncrement(f);
        const mrpt::obs::CSensoryFrame sf = hymm::sim::sensoryFrame(f);
        for (DenseSlam* slam : {off.get(), on.get()})
        {
            slam->processOdometry(odo);
            slam->processFrame(sf);
        }
        const double t = mrpt::Clock::toDouble(f.stamp);
        true_path.push_back({t, f.true_pose[0], f.true_pose[1], f.true_pose[2]});
        if (f.scan) scans.push_back({t, hymm::dense::ScanPoints::fromRangeScan(*f.scan)});
    }
    off->refreshRegions();
    on->refreshRegions();

    std::vector<hymm::dense::Polygon> outlines, surfaces;
    for (const auto& o : sim.world().objects())
    {
        const auto poly = o.outlineAt(0);  // static objects
        outlines.emplace_back(poly.begin(), poly.end());
    }
    surfaces = outlines;
    for (const auto& l : sim.world().landmarks()) surfaces.push_back(hymm::dense::circlePolygon(l.position, l.radius));
    hymm::eval::LaserCoverageOptions lo;
    lo.max_range_m = on->hybridMap()->options().max_range_m;
    const auto seen = hymm::eval::laserSeenOutline(scans, true_path, outlines, lo);
    ASSERT_EQ(seen.returns.scans_unmatched, 0u);
    ASSERT_GT(seen.seenFraction(), 0.5);

    const auto pts_off = landmarkFramePoints(*off, sim.world()),
               pts_on = landmarkFramePoints(*on, sim.world());
    const auto fused = fusedPoints(pts_on, pts_off);
    const auto cov_off = hymm::eval::coverageOfSeen(seen, pts_off),
               cov_on = hymm::eval::coverageOfSeen(seen, pts_on);
    const auto acc = hymm::dense::evaluateOutlines(fused, surfaces);
    const auto sensor = hymm::dense::evaluateOutlines(seen.returns.points, surfaces);
    std::printf(
        "seen %zu of %zu outline samples; mapped: off %.3f, on %.3f; fused %zu (pipeline %zu), "
        "mean / p95 "
        "distance %.3f / %.3f m (returns at the true poses %.3f / %.3f m)\n",
        seen.seen_samples, seen.samples.points.size(), cov_off.seen_coverage, cov_on.seen_coverage,
        fused.size(), on->stats().delayed_fused, acc.mean_distance_m, acc.p95_distance_m,
        sensor.mean_distance_m, sensor.p95_distance_m);

    // The fused points are exactly what the pipeline says it fused (UIF: every direct
    // point is the same with and without the store).
    EXPECT_EQ(fused.size(), on->stats().delayed_fused);
    ASSERT_GT(fused.size(), 1000u);
    // Completeness: with the store, >= 95 % of what the laser saw; without, visible holes.
    EXPECT_GE(cov_on.seen_coverage, 0.95);
    EXPECT_GE(cov_on.seen_coverage - cov_off.seen_coverage, 0.02);
    // Accuracy of the fused points: below the mean lateral error of a return at the
    // laser's maximum range from a perfectly known pose, E|N(0, r_max sigma_b)| =
    // sqrt(2/pi) r_max sigma_b (25 m, 1.5 deg: 0.52 m). They were seen from afar and
    // while the vehicle was still uncertain relative to the landmarks around them, so
    // they are less accurate than the returns at the true poses (sensor noise alone),
    // but a fusion at an uncorrected pose or in the wrong frame would be off by metres.
    const double sigma_b = scenario.laser.std_bearing, r_max = scenario.laser.max_range_m;
    EXPECT_LT(acc.mean_distance_m, std::sqrt(2.0 / M_PI) * r_max * sigma_b);
    EXPECT_GT(acc.mean_distance_m, 0.5 * sensor.mean_distance_m);  // not better than the sensor

    // Every stored return is accounted for: fused, evicted, lost or still waiting.
    const auto& st = on->stats();
    EXPECT_EQ(st.delayed_stored,
              st.delayed_fused + st.delayed_evicted + st.delayed_lost +
                  on->delayedStore()->numStoredPoints());
    EXPECT_EQ(off->stats().delayed_stored + off->stats().delayed_outside_potential, 0u);
}

// A small budget binds: the pipeline counts what the store turned away or evicted, and
// the books still balance.
TEST(SinglePassTest, StoreBudgetDropsAreCountedInThePipelineStats)
{
    const auto scenario = hymm::sim::Scenario::fromFile(std::string(HYMM_SOURCE_DIR) +
                                                        "/configs/sim/ch3_single_pass.ini");
    hymm::sim::Simulator sim(scenario);
    const std::string path = std::string(HYMM_SOURCE_DIR) + "/configs/ch3_single_pass_slam.ini";
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    ASSERT_TRUE(in) << path;
    mrpt::config::CConfigFileMemory cfg(text.str());
    cfg.write("DelayedDenseStore", "enabled", true);
    cfg.write("DelayedDenseStore", "max_stored_points", 150);
    cfg.write("DelayedDenseStore", "max_stored_scans", 3);
    std::unique_ptr<DenseSlam> slam(new DenseSlam(DenseSlam::fromConfig(cfg)));
    hymm::sim::SimFrame f;
    size_t max_waiting = 0;
    while (sim.next(f))
    {
        slam->processOdometry(hymm::sim::odometryIncrement(f));
        slam->processFrame(hymm::sim::sensoryFrame(f));
        max_waiting = std::max(max_waiting, slam->delayedStore()->numStoredPoints());
    }
    const auto& st = slam->stats();
    EXPECT_LE(max_waiting, 150u);
    EXPECT_GT(st.delayed_evicted + st.delayed_thinned, 0u) << "the budget never bound";
    EXPECT_GT(st.delayed_fused, 0u);
    EXPECT_EQ(st.delayed_stored, st.delayed_fused + st.delayed_evicted + st.delayed_lost +
                                     slam->delayedStore()->numStoredPoints());
}

}  // namespace
