/**
 * @file motion_truth.h
 * @brief Ground truth of what moved, for the motion layers (thesis Sec. 6.3.3).
 *
 * The simulator knows where every object was and when. These functions turn that into
 * the reference areas a motion detector is scored against:
 *  - fast motion: the footprints an object took while moving (their union is the swept
 *    area), and the points where laser beams met a moving object (its surface as the
 *    sensor saw it, the part an occupancy grid can record at all);
 *  - slow motion: the footprints that differ between two instants (an object removed,
 *    added, or moved: its old and new places).
 */
#pragma once

#include "hymm/sim/World.h"
#include "hymm/sim/geometry.h"

#include <Eigen/Core>
#include <string>
#include <vector>

namespace hymm::sim
{
/** One area whose content changed between two instants. */
struct ChangedArea
{
    enum class Change
    {
        Removed,    //!< present before, absent after (outline: where it was)
        Added,      //!< absent before, present after (outline: where it is)
        MovedFrom,  //!< present at both times, other pose: the old place
        MovedTo     //!< ... and the new place
    };
    long object_id = -1;
    std::string name;
    Change change = Change::Removed;
    Polygon outline;  //!< global
};
const char* changeName(ChangedArea::Change c);

/** Objects whose footprint at `t_after` differs from that at `t_before` (pose change
 *  above 1 mm / 1 mrad, or presence changed). */
std::vector<ChangedArea> changedAreas(const World& world, double t_before, double t_after);

/** Global outlines of every object that moves (WorldObject::moves()), at t0, t0 + dt, ...
 *  up to t1, while present: their union is the swept area. */
std::vector<Polygon> sweptFootprints(const World& world, double t0, double t1, double dt);

/** Global outlines of the objects that never move, appear or disappear. */
std::vector<Polygon> staticOutlines(const World& world);

/** Where the beams of a laser at global pose `sensor` (x, y, phi), `fov` wide [rad],
 *  one beam every `resolution` [rad], met an object that moves (WorldObject::moves())
 *  at time `t` within `max_range` (noise-free). */
std::vector<Vec2> movingObjectHits(const World& world, double t, const Eigen::Vector3d& sensor,
                                   double fov, double resolution, double max_range);

}  // namespace hymm::sim
