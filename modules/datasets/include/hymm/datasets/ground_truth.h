/**
 * @file ground_truth.h
 * @brief Ground-truth helpers shared by the converters: GPS outlier rejection, TUM files
 *        with an explanatory header, and the dead-reckoning path of a written rawlog.
 */
#pragma once

#include <hymm/io/trajectory_io.h>

#include <string>
#include <vector>

namespace hymm::datasets
{
struct ImportSummary;

struct GpsFilterOptions
{
    /** A fix implying a speed above this from the last accepted fix is a jump [m/s]. */
    double max_speed_mps = 15.0;
    /** After this many consecutive rejected fixes the next one is accepted anyway, so a
     *  lasting offset (or a bad first fix) does not reject the rest of the run. */
    size_t reset_after = 5;
};

/**
 * Keeps the usable GPS fixes: drops non-finite ones ("gps_nan"), times not after the last
 * accepted fix ("gps_non_monotonic") and jumps ("gps_jump", see GpsFilterOptions).
 * Gaps are kept as gaps. Counts in `summary`.
 */
std::vector<hymm::io::StampedPose2D> filterGpsFixes(
    const std::vector<hymm::io::StampedPose2D>& raw, const GpsFilterOptions& opts,
    ImportSummary& summary);

/** hymm::io::writeTum followed by '#' lines of `comment` (one per '\n') at the top. */
void writeTumWithComment(const std::string& path,
                         const std::vector<hymm::io::StampedPose2D>& poses,
                         const std::string& comment);

/**
 * Reads a rawlog written by the converters and composes the mean odometry increments:
 * the dead-reckoning pose at each frame's timestamp, starting at the origin. Throws if
 * the file cannot be read or is not in the actions/sensory-frames format.
 */
std::vector<hymm::io::StampedPose2D> deadReckoningFromRawlog(const std::string& path);

}  // namespace hymm::datasets
