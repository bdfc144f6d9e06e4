#include "hymm/eval/ground_truth_io.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hymm::eval
{

std::vector<core::LandmarkRecord> readSimulLandmarksLandmarks(const std::string& path)
{
    // x y z type seenTimesCount timestampLastSeen ID
    constexpr size_t kColumns = 7;
    std::vector<core::LandmarkRecord> out;
    core::readNumberTable(path, "simul-landmarks landmark file",
                          [&](const std::vector<double>& v, size_t lineno) {
        if (v.size() < kColumns)
            throw std::runtime_error(core::tableLocation(path, lineno) + "expected " + std::to_string(kColumns) +
                                     " columns (x y z type seen time ID), got " +
                                     std::to_string(v.size()));
        const double id = v.back();
        if (id != std::floor(id))
            throw std::runtime_error(core::tableLocation(path, lineno) + "landmark ID " + std::to_string(id) +
                                     " is not an integer");
        core::LandmarkRecord r;
        r.id = static_cast<long>(id);
        r.x = v[0];
        r.y = v[1];
        r.extra = {v[2]};
        out.push_back(r);
    });
    return out;
}

std::vector<core::StampedPose2D> readSimulLandmarksPath(const std::string& path, double t0, double dt)
{
    // x y z yaw pitch roll
    constexpr size_t kColumns = 6;
    std::vector<core::StampedPose2D> out;
    core::readNumberTable(path, "simul-landmarks robot path file",
                          [&](const std::vector<double>& v, size_t lineno) {
        if (v.size() != kColumns)
            throw std::runtime_error(core::tableLocation(path, lineno) + "expected 6 columns (x y z yaw pitch "
                                     "roll), got " + std::to_string(v.size()));
        out.push_back(core::StampedPose2D{t0 + dt * static_cast<double>(out.size()), v[0], v[1], v[3]});
    });
    return out;
}

GroundTruth loadSimulLandmarksGroundTruth(const std::string& rawlog_path, double t0, double dt)
{
    GroundTruth gt;
    gt.landmarks = readSimulLandmarksLandmarks(rawlog_path + "_ground_truth.txt");
    gt.path = readSimulLandmarksPath(rawlog_path + "_ground_truth_robot_path.txt", t0, dt);
    gt.path_has_timestamps = false;
    return gt;
}

GroundTruth loadHymmGroundTruth(const std::string& tum_path, const std::string& landmarks_csv)
{
    GroundTruth gt;
    gt.path = core::readTum(tum_path);
    gt.landmarks = core::readLandmarksCsv(landmarks_csv);
    gt.path_has_timestamps = true;
    return gt;
}

}  // namespace hymm::eval
