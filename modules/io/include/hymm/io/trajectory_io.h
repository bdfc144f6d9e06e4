/**
 * @file trajectory_io.h
 * @brief Plain-text trajectory and landmark files shared by the simulator, the SLAM
 *        app and the evaluation code.
 *
 * Trajectories use the TUM format ("t x y z qx qy qz qw", one pose per line, '#'
 * comments), readable by common trajectory evaluation tools; planar poses are stored
 * with z = 0 and a rotation about z. Landmarks use "id,x,y[,extra...]" CSV lines.
 */
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace hymm::io
{
/**
 * Reads a text table of numbers: one row per line, columns separated by spaces, tabs or
 * commas, blank lines and lines starting with '#' or '%' skipped. Calls `row(values,
 * line_number)` for each row; throws std::runtime_error "path:line: ..." on a token that
 * is not a finite number, and "cannot open <what> 'path'" if the file cannot be read.
 * `row` may throw its own errors; prefix them with tableLocation(path, line).
 */
void readNumberTable(const std::string& path, const std::string& what,
                     const std::function<void(const std::vector<double>&, size_t)>& row);

/** "path:line: ", the prefix of table parsing errors. */
std::string tableLocation(const std::string& path, size_t line);

struct StampedPose2D
{
    double t = 0;    //!< timestamp [s] (rawlog time base)
    double x = 0;    //!< [m]
    double y = 0;    //!< [m]
    double phi = 0;  //!< heading [rad]
};

/** Writes a TUM trajectory; throws if the file cannot be written. */
void writeTum(const std::string& path, const std::vector<StampedPose2D>& poses);

/** Reads a TUM trajectory; throws naming the line on malformed or non-finite content. */
std::vector<StampedPose2D> readTum(const std::string& path);

struct LandmarkRecord
{
    long id = -1;
    double x = 0;
    double y = 0;
    std::vector<double> extra;  //!< further columns (radius, covariance entries, ...)
};

/** Writes "id,x,y,extra..." lines after a '#' header line naming the columns. */
void writeLandmarksCsv(
    const std::string& path, const std::vector<LandmarkRecord>& lms, const std::string& header);

/** Reads "id,x,y,..." CSV (comma or whitespace separated, '#' comments). */
std::vector<LandmarkRecord> readLandmarksCsv(const std::string& path);

}  // namespace hymm::io
