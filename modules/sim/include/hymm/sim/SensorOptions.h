/**
 * @file SensorOptions.h
 * @brief Settings every simulated sensor shares: rate, mounting on the vehicle, range,
 *        field of view and noise (keys common to [LaserSimulator] and [LandmarkDetector]).
 *
 * The mounting pose is relative to the vehicle's tracked point (see Vehicle.h). The
 * thesis tracks the laser itself, so the default mounting is zero.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

namespace hymm::sim
{
struct SensorOptions : public mrpt::config::CLoadableOptions
{
    bool enabled = true;
    double period_s = 0.2;            //!< one reading every period (a multiple of dt) [s]
    std::string sensor_label;         //!< CObservation::sensorLabel
    double pose_x_m = 0;              //!< mounting on the vehicle [m]
    double pose_y_m = 0;              //!< [m]
    double pose_yaw = 0;              //!< [rad] (ini: pose_yaw_deg)
    double max_range_m = 25;          //!< [m]
    double fov = M_PI;                //!< field of view, centred ahead [rad] (ini: fov_deg)
    double std_range_m = 0.15;        //!< range noise [m]
    double std_bearing = M_PI / 180;  //!< bearing noise [rad] (ini: std_bearing_deg)

    /** (x, y, yaw) of the sensor on the vehicle, as hymm::core models take it. */
    Eigen::Vector3d mountPose() const { return {pose_x_m, pose_y_m, pose_yaw}; }
    mrpt::poses::CPose3D mountPose3D() const;

protected:
    /** The keys every sensor section has, in the order they are saved. */
    hymm::core::OptionTable commonTable();
};

}  // namespace hymm::sim
