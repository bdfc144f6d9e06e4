#include "hymm/sim/SensorOptions.h"

#include <mrpt/core/bits_math.h>


namespace hymm::sim
{
mrpt::poses::CPose3D SensorOptions::mountPose3D() const
{
    return mrpt::poses::CPose3D(pose_x_m, pose_y_m, 0, pose_yaw, 0, 0);
}

hymm::core::OptionTable SensorOptions::commonTable()
{
    using namespace hymm::core;
    OptionTable t;
    t.flag("enabled", enabled, "simulate this sensor");
    t.real("period_s", period_s, "s", above(0, 3600), "one reading every period (a multiple of [Scenario] dt_s)");
    t.text("sensor_label", sensor_label, "the observations' sensorLabel");
    t.real("pose_x_m", pose_x_m, "m", between(-100, 100), "mounting on the vehicle, forward of the tracked point");
    t.real("pose_y_m", pose_y_m, "m", between(-100, 100), "mounting on the vehicle, left of the tracked point");
    t.degrees("pose_yaw_deg", pose_yaw, between(-360, 360), "mounting heading on the vehicle");
    t.real("max_range_m", max_range_m, "m", above(0, 1e4), "farthest reading");
    t.degrees("fov_deg", fov, above(0, 360), "field of view, centred ahead");
    t.real("std_range_m", std_range_m, "m", between(0, 100), "range noise, 1 sigma");
    t.degrees("std_bearing_deg", std_bearing, between(0, 180), "bearing noise, 1 sigma");
    return t;
}

}  // namespace hymm::sim
