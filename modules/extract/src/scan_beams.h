/**
 * @file scan_beams.h
 * @brief Private helpers shared by the extractors: beam validation and clustering.
 */
#pragma once

#include "hymm/extract/scan_features.h"

#include <Eigen/Core>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <functional>
#include <vector>

namespace hymm::extract::internal
{
/** One beam of a scan after validation. `usable` is false for skipped beams. */
struct Beam
{
    bool usable = false;
    double range = 0;                                 //!< [m]
    double angle = 0;                                 //!< [rad], sensor frame
    Eigen::Vector2d point = Eigen::Vector2d::Zero();  //!< sensor frame [m]
};

/** A run of consecutive usable beams [first, last]. */
struct Cluster
{
    size_t first = 0;
    size_t last = 0;
    size_t size() const { return last - first + 1; }
};

/**
 * Validates every beam: usable iff flagged valid, finite, >= 0, >= min_range and
 * < max_range (a sensor reports "no return" as its maximum range). max_range is the
 * smaller of the option and the scan's own maxRange. Fills `counts`.
 */
std::vector<Beam> classifyBeams(
    const mrpt::obs::CObservation2DRangeScan& scan, double min_range, double max_range,
    BeamCounts& counts);

/**
 * Splits the usable beams into runs where consecutive beams differ in range by at most
 * `range_jump` and `accept(i)` holds for every member. A skipped beam ends a run.
 */
std::vector<Cluster> clusterBeams(
    const std::vector<Beam>& beams, double range_jump, const std::function<bool(size_t)>& accept);

/** The sensor-frame points of a cluster. */
std::vector<Eigen::Vector2d> clusterPoints(const std::vector<Beam>& beams, const Cluster& c);

/** Angular spacing between consecutive beams of the scan [rad] (0 for < 2 beams). */
double beamSpacing(const mrpt::obs::CObservation2DRangeScan& scan);

}  // namespace hymm::extract::internal
