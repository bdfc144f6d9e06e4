/**
 * @file ground_truth_io.h
 * @brief Readers for simulator ground truth: MRPT's `simul-landmarks` app and HYMM's own
 *        simulator.
 *
 * simul-landmarks (MRPT 2.5) writes, next to `<outFile>` in `<outDir>`:
 *  - `<outFile>_ground_truth.txt`: one landmark per line, written by
 *    CLandmarksMap::saveToTextFile as "x y z type seenTimesCount timestampLastSeen ID"
 *    ("%10f %10f %10f %4i %4u %10f %i"); IDs start at 1.
 *  - `<outFile>_ground_truth_robot_path.txt`: '%' comment lines, then one row per
 *    simulation step "x y z yaw pitch roll" (CMatrixDouble::saveToTextFile). Row i is the
 *    true pose at which the observations of step i were taken (the odometry of step i
 *    then moves the robot to row i+1).
 * The path file has NO timestamps, and the rawlog's observation timestamps cannot replace
 * them: MRPT 2.5.8's simul-landmarks stamps each observation with the wall-clock time of
 * generation (microseconds apart; later MRPT versions write i * 1 s instead). Associate
 * such a path with an estimate by step index (TrajectoryEvaluator::Association::Index),
 * or give the rows synthetic times t0 + i * dt to match an estimate stamped the same way.
 *
 * HYMM's simulator writes a TUM path and an "id,x,y,..." landmark CSV; those are read with
 * hymm::io::readTum / readLandmarksCsv (wrapped by loadHymmGroundTruth).
 */
#pragma once

#include <hymm/io/trajectory_io.h>

#include <string>
#include <vector>

namespace hymm::io
{
struct GroundTruth
{
    std::vector<StampedPose2D> path;
    std::vector<LandmarkRecord> landmarks;
    /** False for simul-landmarks: path times are synthetic (t0 + i dt), see the file comment. */
    bool path_has_timestamps = true;
};

/** Reads a simul-landmarks `*_ground_truth.txt`; LandmarkRecord::extra = {z}. Throws naming
 *  the file and line on malformed content. */
std::vector<LandmarkRecord> readSimulLandmarksLandmarks(const std::string& path);

/** Reads a simul-landmarks `*_ground_truth_robot_path.txt` as planar poses (x, y, yaw),
 *  row i stamped t0 + i * dt. Throws on malformed content. */
std::vector<StampedPose2D> readSimulLandmarksPath(
    const std::string& path, double t0 = 0.0, double dt = 1.0);

/** Both files of a simul-landmarks run, named from the rawlog path
 *  (`<rawlog>_ground_truth.txt`, `<rawlog>_ground_truth_robot_path.txt`). */
GroundTruth loadSimulLandmarksGroundTruth(
    const std::string& rawlog_path, double t0 = 0.0, double dt = 1.0);

/** HYMM simulator ground truth: TUM path and landmark CSV. */
GroundTruth loadHymmGroundTruth(const std::string& tum_path, const std::string& landmarks_csv);

/**
 * Loads ground truth in either supported format, chosen per file:
 *  - MRPT simul-landmarks (`*_ground_truth_robot_path.txt`, `*_ground_truth.txt`):
 *    the path has no timestamps; row i is matched with the i-th estimated pose;
 *  - HYMM (TUM path, `id,x,y,...` landmark CSV): matched by timestamp.
 * Either file may be empty (not given). Throws on unreadable or malformed files.
 */
GroundTruth loadGroundTruth(const std::string& path_file, const std::string& landmarks_file);

}  // namespace hymm::io
