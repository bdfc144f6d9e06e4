/**
 * @file ScanPoints.h
 * @brief A 2D laser scan as the dense layers consume it.
 *
 * Returns are given in the sensor frame; the sensor's mounting pose on the vehicle
 * comes with the scan (from the observation's sensorPose, never a constant). toWorld()
 * places the scan at a vehicle pose: each beam becomes a segment from the sensor to
 * its return, or, for returns beyond the maximum range, a free segment cut at that
 * range with no return.
 *
 * Beams that returned nothing are kept apart, as bearings (`no_return_bearings`): a
 * beam with no echo says that nothing reflective stood along it up to the sensor's
 * reach, but dark, specular or steeply inclined surfaces also send no echo back, so it
 * is evidence of free space only up to some range. toWorld() turns them into free
 * segments only when given that range (HybridMetricMap's `no_return_free_range_m`,
 * default 0 = off); otherwise they are ignored as before.
 */
#pragma once

#include <Eigen/Core>
#include <mrpt/math/TPose2D.h>

#include <vector>

namespace mrpt::obs
{
class CObservation2DRangeScan;
}

namespace hymm::dense
{
/** A beam placed in the global frame. */
struct WorldBeam
{
    Eigen::Vector2d end;  //!< the return, or the point at max range
    bool hit = true;      //!< false: nothing was returned within max range
    /** Index of the return in ScanPoints::points, or (no_return) of the bearing in
     *  ScanPoints::no_return_bearings. */
    size_t source = 0;
    bool no_return = false;  //!< a beam that returned nothing (always hit = false)
};

struct WorldScan
{
    Eigen::Vector2d sensor = Eigen::Vector2d::Zero();
    /** Beams of the returns (in ScanPoints::points order), then the no-return beams. */
    std::vector<WorldBeam> beams;
    Eigen::Vector2d lo = Eigen::Vector2d::Zero();  //!< bounding box of sensor and beam ends
    Eigen::Vector2d hi = Eigen::Vector2d::Zero();
    size_t beyond_range = 0;  //!< returns cut at max range
    size_t no_return = 0;     //!< no-return beams made free segments
};

struct ScanPoints
{
    mrpt::math::TPose2D sensor_on_vehicle{0, 0, 0};  //!< sensor pose in the vehicle frame
    std::vector<Eigen::Vector2d> points;             //!< returns in the sensor frame [m]
    /** The raw (range [m], bearing [rad]) of each return, parallel to `points`, as the
     *  sensor gave it (fromRangeScan() fills it); empty = derived from `points` (see
     *  rangeBearing()). The delayed store keeps returns as this measurement (Eq. 3.25). */
    std::vector<Eigen::Vector2d> range_bearing;
    /** Optional per-return scalar (laser intensity, elevation, another sensor's value),
     *  parallel to `points`; empty = none. Read by PropertyLayer. */
    std::vector<double> values;
    /** Optional 1-sigma of each value, parallel to `values`; empty = the layer default. */
    std::vector<double> value_stds;
    /** Range / bearing noise of the returns [m], [rad]; 0 = unknown, the layers use
     *  their configured noise (ParticlesLayer, SogLayer). */
    double range_std_m = 0.0;
    double bearing_std_rad = 0.0;
    /** Sensor-frame bearings [rad] of the beams that returned nothing (see the file
     *  comment); they carry no range, value or property. */
    std::vector<double> no_return_bearings;
    /** Readings fromRangeScan() dropped: flagged valid but with a range that cannot be
     *  placed (NaN, infinite, <= 0). Not no-return beams: a failed reading says nothing
     *  about free space. */
    size_t skipped = 0;

    /** An MRPT range scan, with its sensorPose projected to 2D: a beam flagged valid
     *  with a finite range > 0 is a return (kept in `points`, its intensity in `values`
     *  when the scan hasIntensity()); a beam flagged invalid is a no-return beam (its
     *  bearing in `no_return_bearings`: the car-park importer, the MRPT drivers and the
     *  simulator's LaserSimulator all flag "no echo within max range" this way; a
     *  driver that also flags too-near or dazzled readings invalid makes those look
     *  like no-return beams too); a valid beam with a NaN, infinite or non-positive
     *  range is counted in `skipped`. The noise arguments fill range_std_m /
     *  bearing_std_rad (obs.stdError is not used: MRPT defaults it to 0.01 m whether or
     *  not the driver knows the noise). */
    static ScanPoints fromRangeScan(
        const mrpt::obs::CObservation2DRangeScan& obs, double range_std_m = 0.0,
        double bearing_std_rad = 0.0);

    /** (range, bearing) of return `i` in the sensor frame: range_bearing[i] when given,
     *  else the polar form of points[i]. */
    Eigen::Vector2d rangeBearing(size_t i) const;

    /** Throws std::invalid_argument if values / value_stds / range_bearing have a size
     *  other than 0 or points.size(), a value is not finite, a value std is not finite and > 0, a noise
     *  std is negative or NaN, or a no-return bearing is not finite. */
    void validate() const;

    /** Beams in the global frame for the vehicle at `vehicle_pose`; returns farther
     *  than `max_range_m` become free beams cut at that range. Zero-length returns
     *  are dropped. With `no_return_free_range_m` > 0 every no-return bearing becomes a
     *  free beam (hit = false, no_return = true) cut at min(no_return_free_range_m,
     *  max_range_m), appended after the returns; 0 leaves them out. Throws
     *  std::invalid_argument if no_return_free_range_m is negative or NaN. */
    WorldScan toWorld(
        const mrpt::math::TPose2D& vehicle_pose, double max_range_m,
        double no_return_free_range_m = 0.0) const;
};

}  // namespace hymm::dense
