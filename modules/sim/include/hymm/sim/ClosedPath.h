/**
 * @file ClosedPath.h
 * @brief A closed loop through waypoints, with corners optionally rounded by circular
 *        arcs, parametrised by arc length: the course the simulated vehicle drives.
 */
#pragma once

#include <vector>

#include "hymm/sim/geometry.h"

namespace hymm::sim
{
class ClosedPath
{
public:
    /**
     * The loop visits `waypoints` in order and returns to the first. Each corner is
     * replaced by an arc of `corner_radius` [m] (smaller where the adjacent segments are
     * too short to hold it; 0 keeps sharp corners). Arc length s = 0 is the first
     * waypoint, or the start of its arc when it is a rounded corner. Throws
     * std::invalid_argument with fewer than 3 waypoints, repeated consecutive waypoints
     * or a U-turn (a corner that reverses the direction).
     */
    ClosedPath(const std::vector<Vec2>& waypoints, double corner_radius);

    double length() const { return cum_.back(); }

    /** Point at arc length `s` (any real: wrapped onto the loop). */
    Vec2 pointAt(double s) const;

    /** Direction of travel at `s` [rad]. */
    double headingAt(double s) const;

    /** Arc length of the point of the loop nearest to `p` among those with unwrapped arc
     *  length in [hint - back, hint + ahead]; returns the unwrapped value (it keeps
     *  growing lap after lap), or `hint` if no segment lies in the window. */
    double project(const Vec2& p, double hint, double back, double ahead) const;

    /** Distance from `p` to the loop (the line, not the enclosed area). */
    double distanceTo(const Vec2& p) const;

    /** The polyline (arcs discretised), without repeating the first vertex. */
    const Polygon& vertices() const { return pts_; }

private:
    size_t segmentAt(double s_wrapped) const;

    Polygon pts_;
    std::vector<double> cum_;  //!< cum_[i]: arc length at pts_[i]; back() = length
};

}  // namespace hymm::sim
