// Scan-SLAM through the pipeline (DenseSlam with landmark_source = scan_landmarks, the
// chapter-5 configs) on short simulated runs of the chapter-5 world, scored against the
// simulator's truth: path and landmark pose errors, and the vehicle NEES over several
// seeds inside the chi-square band.
#include <gtest/gtest.h>
#include <hymm/app/ScanSlamStudy.h>
#include <hymm/core/config_utils.h>
#include <hymm/dense/ScanPoints.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/denseslam/dense_gaussians.h>
#include <hymm/eval/nees.h>
#include <hymm/sim/Simulator.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CSimplePointsMap.h>

#include "sim_feed.h"

#include <cmath>
#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
const std::string kRoot = HYMM_SOURCE_DIR;

hymm::sim::Scenario shortRun(long seed, double duration_s)
{
    auto s = hymm::sim::Scenario::fromFile(kRoot + "/configs/sim/ch5_scanslam.ini");
    s.run.seed = seed;
    s.run.duration_s = duration_s;
    return s;
}

// What the pipeline achieves today on the Table 5.1 noise (docs/results.md, "Scan-SLAM"):
// landmarks made, observed and kept finite, and the path much closer to the truth than
// the odometry alone. The vehicle NEES is recorded, not asserted: three 45 s runs are too
// few for the run-averaged band (over five sets of 20 seeds of the 315 s run it is above
// the band on at most one step and below it on 0.17-0.93 of the steps: docs/results.md,
// "Keyframe scan odometry with the correlated share as a state").
TEST(ScanSlamPipeline, Chapter5WorldBeatsOdometryAndStaysFinite)
{
    const auto cfg = hymm::core::openConfigFile(kRoot + "/configs/ch5_scanslam.ini");
    constexpr int kSeeds = 3;
    constexpr double kDuration = 45;  // [s] 135 m: the first straight and corner
    std::vector<double> nees_sum;
    double slam_sum = 0, dr_sum = 0;
    for (int seed = 1; seed <= kSeeds; ++seed)
    {
        const auto run = hymm::app::runScanSlamStudy(shortRun(seed, kDuration), *cfg);
        SCOPED_TRACE("seed " + std::to_string(seed));
        ASSERT_FALSE(run.steps.empty());
        if (nees_sum.empty()) nees_sum.assign(run.steps.size(), 0.0);
        ASSERT_EQ(run.steps.size(), nees_sum.size());
        for (size_t i = 0; i < run.steps.size(); ++i)
        {
            ASSERT_TRUE(run.steps[i].estimate.allFinite());
            ASSERT_TRUE(run.steps[i].cov.allFinite());
            nees_sum[i] += run.steps[i].nees;
        }
        size_t created = 0, updated = 0;
        for (const auto& [k, n] : run.counters)
        {
            if (k == "scan_landmarks.created") created = n;
            if (k == "scan_landmarks.updated") updated = n;
        }
        EXPECT_GE(created, 8u);
        EXPECT_GE(updated, 3 * created);
        EXPECT_EQ(run.after_closure.landmarks, created);
        // Every run closer to the truth than its dead reckoning.
        EXPECT_LT(run.path_rmse_m, 0.9 * run.dead_reckoning_rmse_m);
        slam_sum += run.path_rmse_m;
        dr_sum += run.dead_reckoning_rmse_m;
    }
    // Over the seeds, well below the odometry's error (measured: 58 % of it).
    EXPECT_LT(slam_sum, 0.7 * dr_sum);
    for (auto& v : nees_sum) v /= kSeeds;
    const auto band = hymm::eval::averageNeesBounds(3, kSeeds, 0.95);
    RecordProperty("vehicle_nees_fraction_inside_95",
                   std::to_string(hymm::eval::fractionInsideBounds(nees_sum, band)));
}

// DenseSLAM on scan landmarks (thesis 6.2): with [DenseSlam] pose_landmark_vertices the
// triangles of the partition are made of scan landmarks, so a world without a single point
// landmark gets a dense map, closer to the true outlines than the same returns placed at
// the filter's pose of their scan; without it there is no region at all. The feature map
// is the same either way (one-way information flow).
TEST(ScanSlamPipeline, RegionsOnScanLandmarksMakeADenseMapOfAWorldWithoutPoints)
{
    constexpr double kDuration = 120;  // [s]
    std::stringstream ini;
    ini << std::ifstream(kRoot + "/configs/ch5_scanslam.ini").rdbuf();
    const std::string dense = "\n[LtrPartition]\nmax_edge_length_m = 80\nsearch_radius_m = 60\n"
                              "[HybridMetricMap]\nmax_range_m = 25\n[OccupancyLayer]\ncell_size_m = 0.2\n";
    std::vector<Eigen::Vector3d> final_pose;
    // Dense map / at-the-time mean distance per seed where regions formed: a single run's
    // comparison depends on that run's corrections.
    std::vector<double> ratio;
    constexpr long kSeeds = 8;
    for (long seed = 1; seed <= kSeeds; ++seed)
    for (const bool on : {false, true})
    {
        if (!on && seed > 1) continue;  // the run without pose vertices: seed 1 only
        SCOPED_TRACE((on ? "pose landmark vertices, seed " : "point landmark vertices only, seed ") +
                     std::to_string(seed));
        std::string text = ini.str();
        text.replace(text.find("landmark_source = scan_landmarks"), 32,
                     std::string("landmark_source = scan_landmarks\ndense_layers = points,occupancy\n"
                                 "pose_landmark_vertices = ") + (on ? "true" : "false"));
        mrpt::config::CConfigFileMemory cfg(text + dense);
        // The thesis' pipeline, without the scan odometry and the apparent poses of the
        // shipped config, for the same reason as the raw odometry below: the comparison
        // needs a filter that drifts by metres between template observations.
        cfg.write("ScanOdometry", "enabled", "false");
        cfg.write("ScanLandmarks", "view_corr_share", "0");
        auto slam = hymm::denseslam::DenseSlam::fromConfig(cfg);
        auto scenario = shortRun(seed, kDuration);
        // The raw (heading-biased) odometry of earlier versions: the comparison below
        // needs a filter that drifts by metres within the run. With the bias corrected
        // the returns placed at the time are within ~2 m of the outlines and regions on
        // scan landmarks form later (none within 120 s on seeds 1, 3, 5): docs/results.md,
        // "Odometry bias from the steering noise".
        scenario.vehicle.odometry_bias_correction = false;
        hymm::sim::Simulator sim(scenario);
        // The same returns placed at the filter's pose of their scan (a map with no later
        // correction), every fifth scan.
        std::vector<Eigen::Vector2d> at_the_time;
        size_t scans = 0;
        hymm::denseslam::testing::runFrames(sim, slam, [&](const hymm::sim::SimFrame& f) {
            if (!f.scan || scans++ % 5 != 0) return;
            const Eigen::Vector3d v = slam.ekf().vehiclePose();
            // Returns within 25 m (the dense range), placed as the pipeline places them.
            const auto world = hymm::dense::ScanPoints::fromRangeScan(*f.scan).toWorld({v[0], v[1], v[2]}, 25.0);
            for (const auto& b : world.beams)
                if (b.hit) at_the_time.push_back(b.end);
        });
        final_pose.push_back(slam.ekf().vehiclePose());
        ASSERT_NE(slam.partition(), nullptr);
        if (!on)
        {
            EXPECT_EQ(slam.partition()->size(), 0u);
            EXPECT_EQ(slam.stats().returns_stored, 0u);
            continue;
        }
        // No region within 120 s on some seeds (seeds 3 and 5 with first-estimates
        // Jacobians): nothing to compare there.
        if (seed > 1 && (slam.partition()->size() < 2 || slam.stats().returns_stored <= 20)) continue;
        EXPECT_GE(slam.partition()->size(), 2u);
        ASSERT_GT(slam.stats().returns_stored, 20u);
        for (long rid : slam.partition()->regionIds())
            for (long v : slam.partition()->region(rid).vertex_ids)
                EXPECT_TRUE(slam.virtualLandmarkIds().count(v) || slam.ekf().landmarkBlock(v).dim == 3)
                    << "region " << rid << " vertex " << v;
        mrpt::maps::CSimplePointsMap pts;
        slam.hybridMap()->renderPoints(*slam.partition(), pts);
        std::vector<Eigen::Vector2d> p;
        for (size_t i = 0; i < pts.size(); ++i)
        {
            float x, y;
            pts.getPoint(i, x, y);
            p.emplace_back(x, y);
        }
        std::vector<hymm::dense::Polygon> outlines;
        for (const auto& o : sim.world().objects())
        {
            const auto poly = o.outlineAt(0.0);
            outlines.emplace_back(poly.begin(), poly.end());
        }
        const auto m = hymm::dense::evaluateOutlines(p, outlines);
        const auto then = hymm::dense::evaluateOutlines(at_the_time, outlines);
        RecordProperty("dense_mean_distance_m", std::to_string(m.mean_distance_m));
        RecordProperty("at_the_time_mean_distance_m", std::to_string(then.mean_distance_m));
        // Measured (configs/ch5_scanslam.ini, first-estimates Jacobians): seed 1 stores 64
        // returns 4.29 m from the outlines against 4.66 m for the returns placed at the
        // filter's pose of their scan (the path is off by metres: Scan-SLAM's own error,
        // docs/results.md); on the 5 seeds of 1-8 with two regions or more the ratio is
        // 0.26-0.92, median 0.50.
        // Every stored return is rendered on seed 1; elsewhere a region can be full (the
        // points layer's max_points / max_points_per_cell bounds thin it).
        if (seed == 1)
            EXPECT_EQ(p.size(), slam.stats().returns_stored);
        else
            EXPECT_LE(p.size(), slam.stats().returns_stored);
        ratio.push_back(m.mean_distance_m / then.mean_distance_m);
        // What augments a template (thesis 6.2): the same stored returns, read back from
        // the regions meeting a box at their current affine maps, exactly those inside it.
        Eigen::Vector2d lo = p.front(), hi = p.front();
        for (const auto& q : p) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
        lo.array() -= 0.01;  // p went through float (CSimplePointsMap)
        hi.array() += 0.01;
        for (const double shrink : {0.0, 0.3})
        {
            const Eigen::Vector2d blo = lo + shrink * (hi - lo), bhi = hi - shrink * (hi - lo);
            hymm::denseslam::DenseGaussiansStats st;
            const auto g = hymm::denseslam::denseGaussiansInBox(*slam.partition(), *slam.hybridMap(), blo, bhi,
                                                                0.1, &st);
            size_t expected = 0;
            for (const auto& q : p) expected += (q.array() >= blo.array()).all() && (q.array() <= bhi.array()).all();
            EXPECT_EQ(g.size(), expected) << "shrink " << shrink;
            for (size_t i = 0; i < g.size(); ++i)
            {
                EXPECT_TRUE((g.points[i].array() >= blo.array()).all() && (g.points[i].array() <= bhi.array()).all());
                EXPECT_GE(g.covs[i].determinant(), 0.0);
            }
            if (shrink == 0.0)
            {
                EXPECT_GE(st.regions, 1u);
                EXPECT_LE(st.regions, slam.partition()->size());
                EXPECT_GE(st.read, g.size());
                EXPECT_NEAR(hymm::dense::evaluateOutlines(g.points, outlines).mean_distance_m, m.mean_distance_m, 1e-3);
            }
        }
    }
    EXPECT_EQ(final_pose[0], final_pose[1]);
    // The landmark corrections reach the dense map: closer to the outlines than the same
    // returns at the time in most seeds, and by a margin at the median.
    ASSERT_GE(ratio.size(), 5u);
    std::vector<double> sorted = ratio;
    std::sort(sorted.begin(), sorted.end());
    const double median = 0.5 * (sorted[(sorted.size() - 1) / 2] + sorted[sorted.size() / 2]);
    RecordProperty("dense_to_at_the_time_median", std::to_string(median));
    std::string all;
    for (double r : ratio) all += (all.empty() ? "" : " ") + std::to_string(r);
    RecordProperty("dense_to_at_the_time_per_seed", all);
    EXPECT_LT(median, 0.85);
    const auto closer = std::count_if(ratio.begin(), ratio.end(), [](double r) { return r < 1.0; });
    EXPECT_GE(3 * closer, 2 * static_cast<long>(ratio.size()));
}

}  // namespace
