/**
 * @file sim_scenes.h
 * @brief Scans of known polygons from hymm::sim for the scanslam tests.
 */
#pragma once

#include <hymm/scanslam/PointSet.h>
#include <hymm/sim/LaserSimulator.h>
#include <hymm/sim/World.h>

#include <mrpt/core/Clock.h>

namespace hymm::scanslam::testing
{
/** An object of `outline` (object frame) fixed at (x, y, yaw). */
inline sim::WorldObject fixedObject(long id, sim::Polygon outline, double x, double y, double yaw)
{
    sim::WorldObject o;
    o.id = id;
    o.name = "o" + std::to_string(id);
    o.outline = std::move(outline);
    o.trajectory = {sim::PoseKey{0, x, y, yaw}};
    return o;
}

inline sim::Polygon box(double l, double w)
{
    return {{-l / 2, -w / 2}, {l / 2, -w / 2}, {l / 2, w / 2}, {-l / 2, w / 2}};
}

/** Two boxes and a thin wall ahead of the origin, well apart. */
inline sim::World threeObjects()
{
    std::vector<sim::WorldObject> objs;
    objs.push_back(fixedObject(0, box(4, 3), 9, 4, 0.5));     // seen corner-on: an L
    objs.push_back(fixedObject(1, box(3, 2), 8, -6, -0.3));
    objs.push_back(fixedObject(2, box(6, 0.2), 16, 0, M_PI / 2));  // a straight wall
    return sim::World({}, std::move(objs));
}

/** A room of boxes and walls around the origin: every direction has structure. */
inline sim::World room()
{
    std::vector<sim::WorldObject> objs;
    objs.push_back(fixedObject(0, box(4, 3), 9, 4, 0.5));
    objs.push_back(fixedObject(1, box(3, 2), 8, -6, -0.3));
    objs.push_back(fixedObject(2, box(20, 0.3), 0, 12, 0));
    objs.push_back(fixedObject(3, box(20, 0.3), 0, -12, 0));
    objs.push_back(fixedObject(4, box(0.3, 24), 15, 0, 0));
    objs.push_back(fixedObject(5, box(2, 2), -4, 6, 0.2));
    return sim::World({}, std::move(objs));
}

struct Laser
{
    double std_range_m = 0.05;
    double std_bearing_deg = 0.5;
    double max_range_m = 30;
    double resolution_deg = 0.5;

    ScanNoise noise() const { return {std_range_m, std_bearing_deg * M_PI / 180}; }
};

/** A scan from the vehicle at global `pose`, 180 deg field of view, the laser mounted
 *  at `mount` on the vehicle. */
inline mrpt::obs::CObservation2DRangeScan::Ptr simulatedScan(const sim::World& world, const Vec3& pose, uint32_t seed,
                                                             const Laser& laser = {},
                                                             const Vec3& mount = Vec3::Zero())
{
    sim::LaserSimulator::Options o;
    o.max_range_m = laser.max_range_m;
    o.fov = M_PI;
    o.resolution = laser.resolution_deg * M_PI / 180;
    o.std_range_m = laser.std_range_m;
    o.std_bearing = laser.std_bearing_deg * M_PI / 180;
    o.pose_x_m = mount.x();
    o.pose_y_m = mount.y();
    o.pose_yaw = mount.z();
    sim::LaserSimulator sim(o, seed, seed + 1000);
    return sim.observe(world, Eigen::Vector3d(pose.x(), pose.y(), pose.z()), 0.0, mrpt::Clock::now());
}

/** The points of simulatedScan() from the sensor at global `pose` (no mounting). */
inline PointSet simulate(const sim::World& world, const Vec3& pose, uint32_t seed,
                         const Laser& laser = {}, ScanReadStats* stats = nullptr)
{
    return fromScan(*simulatedScan(world, pose, seed, laser), laser.noise(), stats);
}

}  // namespace hymm::scanslam::testing
