#include "hymm/sim/SensorOptions.h"

#include <hymm/core/config_utils.h>
#include <mrpt/core/bits_math.h>

#include "config_text.h"

namespace hymm::sim
{
using hymm::core::readDoubleMin;

mrpt::poses::CPose3D SensorOptions::mountPose3D() const
{
    return mrpt::poses::CPose3D(pose_x_m, pose_y_m, 0, pose_yaw, 0, 0);
}

std::vector<std::string> SensorOptions::commonKeys()
{
    return {"enabled",      "period_s",    "sensor_label", "pose_x_m",    "pose_y_m",
            "pose_yaw_deg", "max_range_m", "fov_deg",      "std_range_m", "std_bearing_deg"};
}

void SensorOptions::loadCommon(const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    enabled = hymm::core::readBool(cfg, s, "enabled", enabled);
    period_s = readDoubleMin(cfg, s, "period_s", period_s, 0.0, true);
    sensor_label = hymm::core::readString(cfg, s, "sensor_label", sensor_label);
    pose_x_m = hymm::core::readDouble(cfg, s, "pose_x_m", pose_x_m);
    pose_y_m = hymm::core::readDouble(cfg, s, "pose_y_m", pose_y_m);
    pose_yaw =
        mrpt::DEG2RAD(hymm::core::readDouble(cfg, s, "pose_yaw_deg", mrpt::RAD2DEG(pose_yaw)));
    max_range_m = readDoubleMin(cfg, s, "max_range_m", max_range_m, 0.0, true);
    const double fov_deg = readDoubleMin(cfg, s, "fov_deg", mrpt::RAD2DEG(fov), 0.0, true);
    if (fov_deg > 360)
        hymm::core::throwConfigError(s, "fov_deg", detail::formatNumber(fov_deg), "must be <= 360");
    fov = mrpt::DEG2RAD(fov_deg);
    std_range_m = readDoubleMin(cfg, s, "std_range_m", std_range_m, 0.0, false);
    std_bearing = mrpt::DEG2RAD(
        readDoubleMin(cfg, s, "std_bearing_deg", mrpt::RAD2DEG(std_bearing), 0.0, false));
}

void SensorOptions::saveCommon(mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    cfg.write(s, "enabled", std::string(enabled ? "true" : "false"));
    detail::writeNumber(cfg, s, "period_s", period_s);
    cfg.write(s, "sensor_label", sensor_label);
    detail::writeNumber(cfg, s, "pose_x_m", pose_x_m);
    detail::writeNumber(cfg, s, "pose_y_m", pose_y_m);
    detail::writeNumber(cfg, s, "pose_yaw_deg", mrpt::RAD2DEG(pose_yaw));
    detail::writeNumber(cfg, s, "max_range_m", max_range_m);
    detail::writeNumber(cfg, s, "fov_deg", mrpt::RAD2DEG(fov));
    detail::writeNumber(cfg, s, "std_range_m", std_range_m);
    detail::writeNumber(cfg, s, "std_bearing_deg", mrpt::RAD2DEG(std_bearing));
}

}  // namespace hymm::sim
