/**
 * @file scan_pairs.h
 * @brief Simulated template/scan pairs for the matcher benchmark and evaluation:
 *        random worlds of boxes and convex polygons around the sensor (sizes and
 *        distances of the chapter-5 simulation), laser of thesis Table 5.1.
 */
#pragma once

#include <hymm/scanslam/PointSet.h>
#include <hymm/scanslam/ScanTemplate.h>
#include <hymm/scanslam/Segmenter.h>
#include <hymm/sim/LaserSimulator.h>
#include <hymm/sim/World.h>
#include <mrpt/core/Clock.h>
#include <mrpt/random/RandomGenerators.h>

#include <cmath>
#include <optional>

namespace hymm::bench
{
using scanslam::PointSet;
using scanslam::Vec2;
using scanslam::Vec3;

/** Thesis Table 5.1 laser: 0.1 m, 1 deg, 35 m; 180 deg at 0.5 deg (361 beams). */
inline sim::LaserSimulator::Options table51Laser()
{
    sim::LaserSimulator::Options o;
    o.max_range_m = 35;
    o.fov = M_PI;
    o.resolution = 0.5 * M_PI / 180;
    o.std_range_m = 0.1;
    o.std_bearing = M_PI / 180;
    return o;
}

/** 6 objects (boxes or random convex polygons, 3-10 m across) 6-20 m ahead. */
inline sim::World randomWorld(mrpt::random::CRandomGenerator& rng)
{
    std::vector<sim::WorldObject> objs;
    for (long k = 0; k < 6; ++k)
    {
        sim::WorldObject o;
        o.id = k;
        o.name = "o" + std::to_string(k);
        const double size = rng.drawUniform(3, 10);
        const int nv = static_cast<int>(rng.drawUniform(3, 7));
        if (nv <= 3)
            o.outline = {{-size / 2, -size / 4}, {size / 2, -size / 4}, {size / 2, size / 4}, {-size / 2, size / 4}};
        else
            for (int v = 0; v < nv; ++v)
            {
                const double a = 2 * M_PI * v / nv + rng.drawUniform(-0.3, 0.3);
                const double r = 0.5 * size * rng.drawUniform(0.6, 1.0);
                o.outline.emplace_back(r * std::cos(a), r * std::sin(a));
            }
        // Spread over bearings so objects rarely occlude each other.
        const double bearing = -1.3 + 2.6 * (k + rng.drawUniform(0.2, 0.8)) / 6;
        const double dist = rng.drawUniform(8, 20);
        o.trajectory = {sim::PoseKey{0, dist * std::cos(bearing), dist * std::sin(bearing),
                                     rng.drawUniform(-M_PI, M_PI)}};
        objs.push_back(o);
    }
    return sim::World({}, std::move(objs));
}

inline PointSet simulateScan(const sim::World& world, const Vec3& pose, uint32_t seed,
                             const sim::LaserSimulator::Options& laser)
{
    sim::LaserSimulator las(laser, seed, seed + 7919);
    const auto scan = las.observe(world, Eigen::Vector3d(pose.x(), pose.y(), pose.z()), 0.0,
                                  mrpt::Clock::now());
    return scanslam::fromScan(*scan, {laser.std_range_m, laser.std_bearing});
}

struct ScanPair
{
    scanslam::ScanTemplate tpl;
    PointSet scan;
    Vec3 truth;  //!< template frame in the second scan's frame
};

/** A pair: template = the largest segment of the scan from A (at least `min_points`),
 *  scan from B = A moved by up to 1 m and 10 deg. nullopt if no segment. */
inline std::optional<ScanPair> randomPair(mrpt::random::CRandomGenerator& rng, uint32_t seed,
                                          size_t min_points = 30, double std_range = 0.1,
                                          double std_bearing = M_PI / 180)
{
    const sim::World world = randomWorld(rng);
    auto laser = table51Laser();
    laser.std_range_m = std_range;
    laser.std_bearing = std_bearing;
    const Vec3 a(0, 0, 0);
    const Vec3 b(rng.drawUniform(-1, 1), rng.drawUniform(-1, 1), rng.drawUniform(-0.17, 0.17));
    const PointSet sa = simulateScan(world, a, seed, laser);
    scanslam::Segmenter::Options so;
    so.min_points = min_points;
    so.max_range_gap_m = 0.5;
    const auto segs = scanslam::Segmenter(so).segment(sa);
    if (segs.empty()) return std::nullopt;
    size_t best = 0;
    for (size_t k = 1; k < segs.size(); ++k)
        if (segs[k].size() > segs[best].size()) best = k;
    ScanPair p;
    p.tpl = scanslam::ScanTemplate::fromSegment(sa, segs[best]);
    p.scan = simulateScan(world, b, seed + 1, laser);
    p.truth = scanslam::compose(scanslam::inverse(b), p.tpl.frame_in_sensor);
    return p;
}

}  // namespace hymm::bench
