/**
 * @file ground_truth_io.h
 * @brief The simulator's object ground truth: a plain text file of true outlines.
 *
 * Format (one closed polygon per line, '#' comments):
 *     id t_from t_to x1 y1 x2 y2 ... xn yn
 * global coordinates [m], counter-clockwise, the last vertex joining the first. The
 * outline is the object's shape at every sensory frame with a timestamp in
 * [t_from, t_to] (rawlog time, seconds as mrpt::Clock::toDouble). A static object has
 * one line spanning the run; a moving object has one line per frame, and an object
 * moved, added or removed between visits one line per stretch it stayed put. Header
 * lines "# object <id> <name> <kind>" name the objects.
 *
 * Surface properties (written when the laser reports intensities), a second text file
 * with '#' comments and one record per line:
 *     field v0 gx gy     value(x, y) = v0 + gx x + gy y on surfaces without their own
 *     landmarks v        every landmark trunk (line absent: the field)
 *     object id v        an object with its own value (objects not listed: the field)
 * The values are the true ones, before the laser's intensity noise and rounding.
 */
#pragma once

#include <string>
#include <vector>

#include "hymm/sim/World.h"

namespace hymm::sim
{
struct ObjectOutlineRecord
{
    long id = -1;
    double t_from = 0;  //!< [s], rawlog time
    double t_to = 0;    //!< [s], rawlog time
    Polygon outline;    //!< global [m]
};

/**
 * Writes the outlines of the world's objects over a run whose frames happened at
 * `frame_t` (seconds from the start, for the world) and `frame_stamps` (the same frames
 * in rawlog time, for the file). Throws if the file cannot be written.
 */
void writeObjectOutlines(const std::string& path, const World& world,
                         const std::vector<double>& frame_t,
                         const std::vector<double>& frame_stamps);

/** Reads the format above; throws naming the line on malformed content. */
std::vector<ObjectOutlineRecord> readObjectOutlines(const std::string& path);

/** Writes the surface properties of `world` (format above). Throws if the file cannot
 *  be written. */
void writeSurfaceProperties(const std::string& path, const World& world);

/** Reads the surface-property format; throws naming the line on malformed content
 *  (unknown record, wrong count, not a number, an object id twice). */
SurfaceProperties readSurfaceProperties(const std::string& path);

}  // namespace hymm::sim
