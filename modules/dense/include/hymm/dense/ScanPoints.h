/**
 * @file ScanPoints.h
 * @brief A 2D laser scan as the dense layers consume it.
 *
 * Returns are given in the sensor frame; the sensor's mounting pose on the vehicle
 * comes with the scan (from the observation's sensorPose, never a constant). toWorld()
 * places the scan at a vehicle pose: each beam becomes a segment from the sensor to
 * its return, or, for returns beyond the maximum range, a free segment cut at that
 * range with no return.
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
    size_t source = 0;    //!< index of the return in ScanPoints::points
};

struct WorldScan
{
    Eigen::Vector2d sensor = Eigen::Vector2d::Zero();
    std::vector<WorldBeam> beams;
    Eigen::Vector2d lo = Eigen::Vector2d::Zero();  //!< bounding box of sensor and beam ends
    Eigen::Vector2d hi = Eigen::Vector2d::Zero();
    size_t beyond_range = 0;  //!< returns cut at max range
};

struct ScanPoints
{
    mrpt::math::TPose2D sensor_on_vehicle{0, 0, 0};  //!< sensor pose in the vehicle frame
    std::vector<Eigen::Vector2d> points;             //!< returns in the sensor frame [m]
    /** Optional per-return scalar (laser intensity, elevation, another sensor's value),
     *  parallel to `points`; empty = none. Read by PropertyLayer. */
    std::vector<double> values;
    /** Optional 1-sigma of each value, parallel to `values`; empty = the layer default. */
    std::vector<double> value_stds;
    /** Range / bearing noise of the returns [m], [rad]; 0 = unknown, the layers use
     *  their configured noise (ParticlesLayer, SogLayer). */
    double range_std_m = 0.0;
    double bearing_std_rad = 0.0;

    /** Valid returns of an MRPT range scan (invalid beams carry no range and are
     *  dropped), with its sensorPose projected to 2D. When the scan hasIntensity(),
     *  `values` holds the intensities of the kept returns. The noise arguments fill
     *  range_std_m / bearing_std_rad (obs.stdError is not used: MRPT defaults it to
     *  0.01 m whether or not the driver knows the noise). */
    static ScanPoints fromRangeScan(
        const mrpt::obs::CObservation2DRangeScan& obs, double range_std_m = 0.0,
        double bearing_std_rad = 0.0);

    /** Throws std::invalid_argument if values / value_stds have a size other than 0 or
     *  points.size(), a value is not finite, a value std is not finite and > 0, or a
     *  noise std is negative or NaN. */
    void validate() const;

    /** Beams in the global frame for the vehicle at `vehicle_pose`; returns farther
     *  than `max_range_m` become free beams cut at that range. Zero-length returns
     *  are dropped. */
    WorldScan toWorld(const mrpt::math::TPose2D& vehicle_pose, double max_range_m) const;
};

}  // namespace hymm::dense
