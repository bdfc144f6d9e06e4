// Motion layers (thesis Sec. 6.3.3) of DenseSlam on the chapter-6 scenes, scored against
// the simulator's truth.
#include "sim_feed.h"

#include <gtest/gtest.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/app/motion_outputs.h>
#include <hymm/core/config_utils.h>
#include <hymm/sim/Simulator.h>
#include <hymm/sim/motion_truth.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace
{
using hymm::denseslam::DenseSlam;
using hymm::dynamic::MotionKind;

const std::string kDir = std::string(HYMM_SOURCE_DIR) + "/configs/sim/";

// The parked sensor of the fast scene: no vehicle uncertainty, so the landmarks are not
// correlated and the correlation conditions of the regions are off (Sec. 3.5 geometry
// conditions only); the landmarks are associated by gating (the detector gives no ids).
std::string fastConfig(const std::string& detector)
{
    return R"([DenseSlam]
landmark_source = bearing_range
use_landmark_ids = false
dense_layers = occupancy
[EkfSlam]
association_method = nn
association_gate_prob = 0.99
creation_gate_prob = 0.9999
[LtrPartition]
min_vertex_correlation = 0
min_vehicle_correlation = 0
min_area_m2 = 1
min_angle_deg = 10
max_edge_length_m = 80
search_radius_m = 60
[HybridMetricMap]
max_range_m = 30
[OccupancyLayer]
cell_size_m = 0.2
[DynamicSlam]
enabled = true
[MotionDetector]
enable_slow = false
)" + detector;
}

struct FastRun
{
    hymm::app::MotionScore score;
    hymm::eval::DetectionScore visible;
};

FastRun runFast(const std::string& detector, long seed)
{
    auto s = hymm::sim::Scenario::fromFile(kDir + "ch6_dynamic_fast.ini");
    s.run.seed = seed;
    mrpt::config::CConfigFileMemory cfg(fastConfig(detector));
    DenseSlam slam = DenseSlam::fromConfig(cfg);
    hymm::sim::Simulator sim(s);
    std::vector<double> scan_times;
    hymm::denseslam::testing::run(s, slam, [&](double t) { scan_times.push_back(t); });
    slam.refreshRegions();
    FastRun r;
    const auto truth = hymm::app::motionTruthFromWorld(sim.world(), 0.0, 20.0, 0.1);
    r.score = hymm::app::scoreMotionLayer(slam, MotionKind::Fast, truth, 0.2, 1);
    // The surface the beams met on the movers: what an occupancy grid can record.
    const auto raster = hymm::app::rasterMotionLayer(slam, MotionKind::Fast, 0.2);
    auto seen = raster.covered;
    std::fill(seen.bits.begin(), seen.bits.end(), std::uint8_t{0});
    for (double t : scan_times)
        for (const auto& p : hymm::sim::movingObjectHits(sim.world(), t, Eigen::Vector3d::Zero(), M_PI,
                                                         0.5 * M_PI / 180, 30.0))
            seen.markPoint(p);
    r.visible = hymm::app::scoreAgainst(raster, seen, 1);
    return r;
}

size_t seedCount()
{
    const char* e = std::getenv("HYMM_MOTION_SEEDS");
    return e ? static_cast<size_t>(std::max(1, std::atoi(e))) : 5;
}

struct Spread
{
    std::vector<double> v;
    double median() const
    {
        auto w = v;
        std::sort(w.begin(), w.end());
        return w[w.size() / 2];
    }
    double min() const { return *std::min_element(v.begin(), v.end()); }
    double max() const { return *std::max_element(v.begin(), v.end()); }
};

// Fig. 6.9: the fast-motion layer against the swept area of the two movers, with and
// without the low-pass, over seeds (HYMM_MOTION_SEEDS, default 5).
TEST(DenseSlamMotion, FastLayerFindsTheMoversAndTheLowPassRemovesStaticContours)
{
    Spread p_lp, r_lp, s_lp, p_raw, r_raw, s_raw, vis_lp;
    for (long seed = 1; seed <= static_cast<long>(seedCount()); ++seed)
    {
        const auto lp = runFast("lowpass_sigma_m = 0.1\n", seed);
        const auto raw = runFast("lowpass = false\n", seed);
        ASSERT_GT(lp.score.covered_cells, 5000u);  // the regions cover the movers' lanes
        p_lp.v.push_back(lp.score.total.precision);
        r_lp.v.push_back(lp.score.total.recall);
        s_lp.v.push_back(lp.score.static_fp_fraction);
        vis_lp.v.push_back(lp.visible.recall);
        p_raw.v.push_back(raw.score.total.precision);
        r_raw.v.push_back(raw.score.total.recall);
        s_raw.v.push_back(raw.score.static_fp_fraction);
        ASSERT_GT(lp.score.static_cells, 0u);
    }
    auto line = [](const char* what, const Spread& s) {
        std::printf("  %-28s median %.3f [%.3f, %.3f]\n", what, s.median(), s.min(), s.max());
    };
    std::printf("fast layer, %zu seeds (tolerance 1 cell of 0.2 m):\n", p_lp.v.size());
    line("low-pass precision", p_lp);
    line("low-pass recall (swept)", r_lp);
    line("low-pass recall (seen face)", vis_lp);
    line("low-pass static outline FP", s_lp);
    line("raw precision", p_raw);
    line("raw recall (swept)", r_raw);
    line("raw static outline FP", s_raw);
    EXPECT_GT(p_lp.min(), 0.85);
    EXPECT_GT(r_lp.min(), 0.15);  // the far side of a mover is never seen
    EXPECT_GT(p_raw.median(), 0.7);
    EXPECT_GT(r_raw.median(), r_lp.median());  // the filter trades recall ...
    EXPECT_LT(s_lp.max(), 0.1);                // ... for static contours
    EXPECT_GT(s_raw.median(), s_lp.median());
}

std::string slowConfig(const std::string& detector)
{
    return hymm::denseslam::testing::dynamicSceneConfig("occupancy", 25.0, R"([OccupancyLayer]
cell_size_m = 0.2
[DynamicSlam]
enabled = true
[MotionDetector]
)" + detector);
}

// Fig. 6.10: full SLAM over three laps; after 100 s one object removed, two added and the
// parked car moved. Scored at the final (loop-corrected) estimates against the truth.
TEST(DenseSlamMotion, SlowLayerFindsTheChangedAreasAfterTheLoop)
{
    auto s = hymm::sim::Scenario::fromFile(kDir + "ch6_dynamic_slow.ini");
    mrpt::config::CConfigFileMemory cfg(slowConfig(""));
    DenseSlam slam = DenseSlam::fromConfig(cfg);
    hymm::sim::Simulator sim(s);
    double t_end = 0;
    hymm::denseslam::testing::run(s, slam, [&](double t) { t_end = t; });
    ASSERT_GT(t_end, 240.0);  // every region's 150 s differencing after the change
    slam.refreshRegions();
    const auto truth = hymm::app::motionTruthFromWorld(sim.world(), 0.0, t_end, 1.0);
    const auto sc = hymm::app::scoreMotionLayer(slam, MotionKind::Slow, truth, 0.2, 1);
    std::printf("slow: P %.3f R %.3f static FP %.3f (%zu/%zu) cells %zu\n", sc.total.precision,
                sc.total.recall, sc.static_fp_fraction, sc.static_marked, sc.static_cells,
                sc.total.detected);
    for (const auto& [n, o] : sc.per_object)
        std::printf("  %s: recall %.3f (%zu/%zu footprint cells)\n", n.c_str(), o.recall, o.truth_found,
                    o.truth);
    // Every changed area a region covers is found. In this scene the removed middle
    // object stands 25 m from both roads, beyond every landmark triangle: no region
    // holds it, so no layer can mark it (the regions grow only among landmarks).
    size_t covered = 0;
    for (const char* n : {"middle", "new_left", "new_right", "car"})
    {
        ASSERT_TRUE(sc.per_object.count(n)) << n;
        const auto& o = sc.per_object.at(n);
        if (o.truth == 0) continue;
        ++covered;
        EXPECT_GT(o.truth_found, 0u) << n;
    }
    EXPECT_GE(covered, 3u);
    EXPECT_GT(sc.total.precision, 0.3);
    EXPECT_LT(sc.static_fp_fraction, 0.05);
    EXPECT_GT(slam.motionHook()->stats().slow_differencings, 0u);
}

// The shipped configs/ch6_dynamic_slow.ini (virtual landmarks 30 m deep, beams with no
// return as free space, the fallback tiles differenced too) on the same scene: regions
// reach the removed middle object and its cells are seen free after it left, so it is
// found with the two added ones; the moved car, in no region on this seed, is found in
// the fallback tiles.
TEST(DenseSlamMotion, ShippedSlowConfigFindsTheRemovedMiddleObject)
{
    auto s = hymm::sim::Scenario::fromFile(kDir + "ch6_dynamic_slow.ini");
    const auto cfg = hymm::core::openConfigFile(std::string(HYMM_SOURCE_DIR) + "/configs/ch6_dynamic_slow.ini");
    DenseSlam slam = DenseSlam::fromConfig(*cfg);
    hymm::sim::Simulator sim(s);
    double t_end = 0;
    hymm::denseslam::testing::run(s, slam, [&](double t) { t_end = t; });
    ASSERT_GT(t_end, 240.0);
    slam.refreshRegions();
    const auto truth = hymm::app::motionTruthFromWorld(sim.world(), 0.0, t_end, 1.0);
    const auto sc = hymm::app::scoreMotionLayer(slam, MotionKind::Slow, truth, 0.2, 1);
    std::printf("slow, shipped config: P %.3f R %.3f static FP %.3f\n", sc.total.precision, sc.total.recall,
                sc.static_fp_fraction);
    for (const char* n : {"middle", "new_left", "new_right", "car"})
    {
        ASSERT_TRUE(sc.per_object.count(n)) << n;
        const auto& o = sc.per_object.at(n);
        std::printf("  %s: recall %.3f (%zu/%zu footprint cells)\n", n, o.recall, o.truth_found, o.truth);
        EXPECT_GT(o.truth, 0u) << n << ": no region or fallback tile covers it";
        EXPECT_GT(o.truth_found, 0u) << n;
    }
    EXPECT_GT(sc.total.precision, 0.5);
    EXPECT_GT(sc.total.recall, 0.1);
    EXPECT_LT(sc.static_fp_fraction, 0.05);
}

}  // namespace
