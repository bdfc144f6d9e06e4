/**
 * @file mrpt_apps.h
 * @brief (tests) MRPT's command-line apps run from a test: whether one is installed, and
 *        icp-slam with MRPT's own demo config made headless.
 */
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

namespace hymm::testing
{
/** MRPT's icp-slam demo config (Debian's libmrpt-dev / mrpt-apps). */
inline const std::string kIcpSlamDemoConfig = "/usr/share/mrpt/config_files/icp-slam/icp-slam_demo_classic.ini";

inline bool mrptAppInstalled(const std::string& app)
{
    return std::system(("command -v " + app + " > /dev/null 2>&1").c_str()) == 0;
}

/** icp-slam and its demo config are both there. */
inline bool icpSlamAvailable()
{
    return mrptAppInstalled("icp-slam") && std::filesystem::exists(kIcpSlamDemoConfig);
}

/** Runs icp-slam on `rawlog` with the demo config, its live 3D window off and its pose
 *  logs on (log_estimated_path.txt, log_odometry_path.txt), writing into `log_dir` (its
 *  config beside it as `log_dir`.ini, its output as `log_dir`.log). Returns the shell's
 *  status of the first command that failed, 0 when both ran. */
inline int runIcpSlam(const std::string& rawlog, const std::string& log_dir)
{
    const std::string ini = log_dir + ".ini";
    const std::string sed = "sed -e 's/^SHOW_PROGRESS_3D_REAL_TIME=1/SHOW_PROGRESS_3D_REAL_TIME=0/' -e "
                            "'s#^logOutput_dir=.*#logOutput_dir=" + log_dir + "#' -e 's/^SAVE_POSE_LOG=0/SAVE_POSE_LOG=1/' " +
                            kIcpSlamDemoConfig + " > '" + ini + "'";
    if (const int rc = std::system(sed.c_str())) return rc;
    return std::system(("icp-slam '" + ini + "' '" + rawlog + "' > '" + log_dir + ".log' 2>&1").c_str());
}

}  // namespace hymm::testing
