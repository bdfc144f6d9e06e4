/**
 * @file sim_feed.h
 * @brief Test helpers: feed a simulated run to a DenseSlam in memory, frame by frame,
 *        as a rawlog would deliver it; look up a simulated object by name.
 */
#pragma once

#include <hymm/denseslam/DenseSlam.h>
#include <hymm/sim/Simulator.h>
#include <hymm/sim/frame_feed.h>

#include <functional>
#include <stdexcept>
#include <string>

namespace hymm::denseslam::testing
{
/** Every frame `sim` has left to `slam` (odometry action, then the sensory frame); calls
 *  `probe(frame)` after each frame. */
inline void runFrames(hymm::sim::Simulator& sim, DenseSlam& slam,
                      const std::function<void(const hymm::sim::SimFrame&)>& probe)
{
    hymm::sim::SimFrame f;
    while (sim.next(f))
    {
        slam.processOdometry(hymm::sim::odometryIncrement(f));
        slam.processFrame(hymm::sim::sensoryFrame(f));
        probe(f);
    }
}

/** As runFrames, with `probe(t)` after each frame. */
inline void run(const hymm::sim::Scenario& s, DenseSlam& slam,
                const std::function<void(double)>& probe)
{
    hymm::sim::Simulator sim(s);
    runFrames(sim, slam, [&](const hymm::sim::SimFrame& f) { probe(f.t); });
}

/** The pipeline of the moving-object scenes (configs/sim/ch6_dynamic_slow_*.ini):
 *  configs/ch3_slam.ini with the landmark ids the detector reports, `layers` as
 *  dense_layers, the map limited to `map_range_m`, then `extra` (more keys of
 *  [HybridMetricMap], further sections). */
inline std::string dynamicSceneConfig(const std::string& layers, double map_range_m,
                                      const std::string& extra = "")
{
    return "[DenseSlam]\nlandmark_source = bearing_range\nuse_landmark_ids = true\n"
           "dense_layers = " + layers + "\n" + R"([EkfSlam]
association_method = nn
association_gate_prob = 0.99
creation_gate_prob = 0.9999
[LtrPartition]
min_vertex_correlation = 0.5
min_vehicle_correlation = 0
correlation_measure = min_canonical
ellipse_sigma = 3
min_area_m2 = 1
min_angle_deg = 10
max_edge_length_m = 80
search_radius_m = 60
[VirtualLandmarks]
enabled = true
min_vehicle_correlation = 0.5
max_depth_m = 20
[HybridMetricMap]
)" +
           "max_range_m = " + std::to_string(map_range_m) + "\n" + extra;
}

inline const hymm::sim::WorldObject& object(const hymm::sim::World& w, const std::string& name)
{
    for (const auto& o : w.objects())
        if (o.name == name) return o;
    throw std::invalid_argument("no object " + name);
}

}  // namespace hymm::denseslam::testing
