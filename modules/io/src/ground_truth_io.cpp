#include "hymm/io/ground_truth_io.h"

#include <mrpt/system/filesystem.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hymm::io
{

std::vector<LandmarkRecord> readSimulLandmarksLandmarks(const std::string& path)
{
    // x y z type seenTimesCount timestampLastSeen ID
    constexpr size_t kColumns = 7;
    std::vector<LandmarkRecord> out;
    readNumberTable(path, "simul-landmarks landmark file",
                          [&](const std::vector<double>& v, size_t lineno) {
        if (v.size() < kColumns)
            throw std::runtime_error(tableLocation(path, lineno) + "expected " + std::to_string(kColumns) +
                                     " columns (x y z type seen time ID), got " +
                                     std::to_string(v.size()));
        const double id = v.back();
        if (id != std::floor(id))
            throw std::runtime_error(tableLocation(path, lineno) + "landmark ID " + std::to_string(id) +
                                     " is not an integer");
        LandmarkRecord r;
        r.id = static_cast<long>(id);
        r.x = v[0];
        r.y = v[1];
        r.extra = {v[2]};
        out.push_back(r);
    });
    return out;
}

std::vector<StampedPose2D> readSimulLandmarksPath(const std::string& path, double t0, double dt)
{
    // x y z yaw pitch roll
    constexpr size_t kColumns = 6;
    std::vector<StampedPose2D> out;
    readNumberTable(path, "simul-landmarks robot path file",
                          [&](const std::vector<double>& v, size_t lineno) {
        if (v.size() != kColumns)
            throw std::runtime_error(tableLocation(path, lineno) + "expected 6 columns (x y z yaw pitch "
                                     "roll), got " + std::to_string(v.size()));
        out.push_back(StampedPose2D{t0 + dt * static_cast<double>(out.size()), v[0], v[1], v[3]});
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
    gt.path = readTum(tum_path);
    gt.landmarks = readLandmarksCsv(landmarks_csv);
    gt.path_has_timestamps = true;
    return gt;
}

namespace
{
bool endsWith(const std::string& s, const std::string& suffix)
{
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace

GroundTruth loadGroundTruth(const std::string& path_file, const std::string& landmarks_file)
{
    GroundTruth gt;
    if (!path_file.empty())
    {
        if (!mrpt::system::fileExists(path_file))
            throw std::runtime_error("ground-truth path file not found: '" + path_file + "'");
        if (endsWith(path_file, "_ground_truth_robot_path.txt"))
        {
            gt.path = readSimulLandmarksPath(path_file);
            gt.path_has_timestamps = false;
        }
        else
        {
            gt.path = readTum(path_file);
        }
    }
    if (!landmarks_file.empty())
    {
        if (!mrpt::system::fileExists(landmarks_file))
            throw std::runtime_error("ground-truth landmark file not found: '" + landmarks_file + "'");
        gt.landmarks = endsWith(landmarks_file, "_ground_truth.txt")
                           ? readSimulLandmarksLandmarks(landmarks_file)
                           : readLandmarksCsv(landmarks_file);
    }
    return gt;
}

}  // namespace hymm::io
