// DenseSlam with high-level landmarks (thesis 6.1.3) on the first lap of the chapter-4
// world (configs/sim/ch4_objects.ini, configs/ch4_hll.ini), simulated in process and
// checked against the simulator's truth: HLLs are found in the dense layers, initialised
// from their next observation and observed by alignment; their templates, placed at the
// filter's estimates, lie on the true object outlines; the vehicle stays consistent.
#include "sim_feed.h"

#include <gtest/gtest.h>
#include <hymm/core/config_utils.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/sim/Scenario.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <Eigen/Cholesky>
#include <cmath>

namespace
{
using hymm::denseslam::DenseSlam;

const std::string kRoot = HYMM_SOURCE_DIR;

TEST(DenseSlamHll, FoundInitialisedAndTrackedOnTheTrueOutlines)
{
    hymm::sim::Scenario sc = hymm::sim::Scenario::fromFile(kRoot + "/configs/sim/ch4_objects.ini");
    // Two laps: the first search that sees two corners of one building within 12 m is
    // the second minute's (the first minute's patch holds one corner); the shipped
    // acceptance rule (12 m of outline) needs no change of the config.
    sc.run.laps = 2;
    sc.run.duration_s = 0;
    mrpt::config::CConfigFile cfg(kRoot + "/configs/ch4_hll.ini");
    DenseSlam slam = DenseSlam::fromConfig(cfg);
    ASSERT_NE(slam.highLevelLandmarks(), nullptr);
    std::vector<double> nees;
    double t_end = 0;
    hymm::sim::Simulator sim(sc);
    hymm::denseslam::testing::runFrames(sim, slam, [&](const hymm::sim::SimFrame& f) {
        Eigen::Vector3d e = slam.ekf().vehiclePose() - f.true_pose;
        e.z() = std::remainder(e.z(), 2 * M_PI);
        nees.push_back(e.dot(slam.ekf().vehicleCov().ldlt().solve(e)));
        t_end = f.t;
    });
    const auto& h = *slam.highLevelLandmarks();
    const auto& st = h.stats();
    // One search per minute of log time.
    EXPECT_EQ(st.searches, static_cast<size_t>(t_end / 60.0));
    EXPECT_GE(st.proposed, 1u);
    ASSERT_GE(st.accepted, 1u);
    EXPECT_EQ(st.proposed, st.accepted + st.rejected_few_gaussians + st.rejected_short_outline + st.rejected_overlap_landmark +
                               st.rejected_overlap_candidate);
    EXPECT_TRUE(slam.ekf().mean().allFinite());

    // Every HLL's template, placed at its frame (the estimate once in the filter, the
    // map's pose at detection before), lies on the true outlines.
    std::vector<hymm::dense::Polygon> outlines;
    for (const auto& o : sim.world().objects()) outlines.push_back(o.outlineAt(t_end));
    // A rectangle around a building's corners may also hold poles the laser saw: they
    // are part of what the dense map holds in it.
    for (const auto& l : sim.world().landmarks()) outlines.push_back(hymm::dense::circlePolygon(l.position, l.radius));
    for (const auto& x : h.hlls())
    {
        const bool in = x.landmark_id >= 0 && slam.ekf().hasLandmark(x.landmark_id);
        const Eigen::Vector3d z = in ? Eigen::Vector3d(slam.ekf().landmarkBlockMean(x.landmark_id).head<3>())
                                     : x.rect.pose();
        std::vector<Eigen::Vector2d> pts;
        for (const auto& p : x.tpl.sog.points) pts.push_back(hymm::scanslam::transformPoint(z, p));
        const auto m = hymm::dense::evaluateOutlines(pts, outlines);
        // A pending HLL sits where the map put it at detection, with the map's error of
        // that moment.
        EXPECT_LT(m.mean_distance_m, 1.0)
            << m.mean_distance_m << " m, HLL " << x.index << " at " << x.rect.pose().transpose();
        // Areas do not overlap: no HLL duplicates another.
        for (const auto& y : h.hlls())
            if (y.index > x.index && y.landmark_id >= 0 && slam.ekf().hasLandmark(y.landmark_id))
            {
                hymm::hll::OrientedRect a, b;
                a.half = x.rect.half;
                b.half = y.rect.half;
                EXPECT_FALSE(hymm::hll::overlaps(a.placed(z), b.placed(slam.ekf().landmarkBlockMean(y.landmark_id).head<3>())))
                    << x.index << " " << y.index;
            }
    }
    // The vehicle: NEES inside chi2(3) 99 % on most steps of one run.
    size_t inside = 0;
    for (double n : nees) inside += n <= 11.34;
    EXPECT_GE(static_cast<double>(inside) / nees.size(), 0.9);
}

TEST(DenseSlamHll, NeedsTheOccupancyAndSogLayers)
{
    mrpt::config::CConfigFileMemory cfg(
        "[DenseSlam]\nlandmark_source = bearing_range\ndense_layers = occupancy\n"
        "[HighLevelLandmarks]\nenabled = true\n");
    EXPECT_THROW(DenseSlam::fromConfig(cfg), std::invalid_argument);
}

}  // namespace
