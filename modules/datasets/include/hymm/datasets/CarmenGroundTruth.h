/**
 * @file CarmenGroundTruth.h
 * @brief Pseudo ground truth for an MRPT laser rawlog from a corrected CARMEN log of the
 *        same run (the Radish "-corrected" logs: scan-matched and loop-closed poses).
 *
 * The corrected log samples the run differently from the rawlog (Intel: 910 corrected
 * scans against the rawlog's 2,726), and the rawlog's timestamps repeat (groups of a dozen
 * scans share one), so poses cannot be paired by time. They are paired by content: a
 * corrected scan whose ranges, at the logs' 1 cm resolution, equal those of exactly one
 * scan of the rawlog is that scan, and its corrected pose becomes the truth of that scan.
 * Equal ranges over a whole 180-beam scan do not happen by chance; scans whose ranges
 * occur more than once in the rawlog (a robot standing still) are left out, and so is a
 * pairing that would go back in the rawlog's order.
 */
#pragma once

#include <hymm/eval/MetricsJson.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <hymm/eval/relative_pose_error.h>
#include <hymm/io/trajectory_io.h>

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace hymm::datasets
{
/** One FLASER line of a CARMEN log: the ranges and the (corrected) robot pose. */
struct CarmenLaserScan
{
    std::vector<double> ranges;  //!< [m]
    Eigen::Vector3d pose = Eigen::Vector3d::Zero();  //!< x, y [m], theta [rad]
    double t = 0;  //!< ipc_timestamp [s]
};

/** Reads every FLASER line of a CARMEN log (plain or gzip-compressed). Other messages are
 *  skipped. Throws std::runtime_error naming the file and line on a malformed FLASER
 *  line (too few fields, a field that is not a finite number, a negative count) or when
 *  the file cannot be opened. */
std::vector<CarmenLaserScan> readCarmenLaserScans(const std::string& path);

/** A rawlog scan paired with a corrected pose. */
struct ScanPoseMatch
{
    size_t scan = 0;  //!< index of the scan among the rawlog's 2D scans, in file order
    double t = 0;     //!< the rawlog scan's timestamp [s] (not unique in every log)
    Eigen::Vector3d pose = Eigen::Vector3d::Zero();  //!< the corrected pose
};

struct ScanPairing
{
    std::vector<ScanPoseMatch> matches;  //!< in the rawlog's order
    size_t rawlog_scans = 0;
    size_t carmen_scans = 0;
    size_t unmatched = 0;     //!< corrected scans equal to no rawlog scan
    size_t ambiguous = 0;     //!< equal to more than one rawlog scan
    size_t out_of_order = 0;  //!< equal to one, but earlier than the previous pairing
};

/** Pairs the 2D range scans of `rawlog` (every CObservation2DRangeScan, in file order,
 *  whether in a sensory frame or alone) with `carmen` by equal ranges, both rounded to
 *  `resolution_m`. Throws on an unreadable rawlog or a resolution <= 0. */
ScanPairing pairScansByRanges(const std::string& rawlog, const std::vector<CarmenLaserScan>& carmen,
                              double resolution_m = 0.01);

/** The poses of `path` (one per rawlog scan, in the rawlog's order: hymm-slam's path.tum
 *  on a log of one scan per frame) at the paired scans, and the corrected poses there.
 *  Throws std::invalid_argument when the path's length is not the rawlog's scan count. */
struct PairedPoses
{
    std::vector<io::StampedPose2D> estimate, truth;
};
PairedPoses posesAtPairs(const std::vector<io::StampedPose2D>& path, const ScanPairing& pairing);

/** A path scored at the paired scans: the absolute error after the least-squares SE(2)
 *  fit over all pairs, and relativePoseError between consecutive pairs. */
struct PairedPathScore
{
    eval::TrajectoryEvaluator::Result absolute;
    eval::RelativePoseError relative;
};
/** Throws as posesAtPairs, and when fewer than two scans are paired. */
PairedPathScore scorePathAtPairs(const std::vector<io::StampedPose2D>& path, const ScanPairing& pairing);

/** hymm-eval --carmen's report: "pairing" (the counts of ScanPairing), "path" (the
 *  absolute error, as hymm-eval's "path") and "relative" (metres and degrees). */
eval::MetricsJson pairedScoreMetrics(const ScanPairing& pairing, const PairedPathScore& score);

}  // namespace hymm::datasets
