#include "hymm/datasets/ground_truth.h"
#include <hymm/core/output_files.h>

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CRawlog.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "hymm/datasets/ImportSummary.h"

namespace hymm::datasets
{
std::vector<hymm::io::StampedPose2D> filterGpsFixes(
    const std::vector<hymm::io::StampedPose2D>& raw, const GpsFilterOptions& opts,
    ImportSummary& summary)
{
    std::vector<hymm::io::StampedPose2D> out;
    size_t rejected_in_a_row = 0;
    for (const auto& p : raw)
    {
        if (!std::isfinite(p.t) || !std::isfinite(p.x) || !std::isfinite(p.y))
        {
            summary.skip("gps_nan");
            continue;
        }
        if (!out.empty() && !(p.t > out.back().t))
        {
            summary.skip("gps_non_monotonic");
            continue;
        }
        if (!out.empty() && rejected_in_a_row < opts.reset_after)
        {
            const auto& q = out.back();
            const double dist = std::hypot(p.x - q.x, p.y - q.y);
            if (dist > opts.max_speed_mps * (p.t - q.t))
            {
                summary.skip("gps_jump");
                ++rejected_in_a_row;
                continue;
            }
        }
        rejected_in_a_row = 0;
        out.push_back(p);
    }
    return out;
}

void writeTumWithComment(const std::string& path,
                         const std::vector<hymm::io::StampedPose2D>& poses,
                         const std::string& comment)
{
    hymm::io::writeTum(path, poses);
    std::ifstream in(path);
    std::stringstream body;
    body << in.rdbuf();
    in.close();
    hymm::core::AtomicTextFile out(path);
    std::istringstream lines(comment);
    std::string line;
    while (std::getline(lines, line)) out << "# " << line << "\n";
    out << body.str();
    out.commit();
}

std::vector<hymm::io::StampedPose2D> deadReckoningFromRawlog(const std::string& path)
{
    mrpt::obs::CRawlog log;
    if (!log.loadFromRawLogFile(path))
        throw std::runtime_error("cannot read rawlog '" + path + "'");
    std::vector<hymm::io::StampedPose2D> out;
    mrpt::poses::CPose2D pose;
    for (size_t i = 0; i < log.size(); ++i)
    {
        if (log.getType(i) != mrpt::obs::CRawlog::etActionCollection) continue;
        const auto acts = log.getAsAction(i);
        const auto mov = acts->getBestMovementEstimation();
        if (!mov)
            throw std::runtime_error("rawlog '" + path + "': entry " + std::to_string(i) +
                                     " has no 2-D odometry");
        pose = pose + mov->poseChange->getMeanVal();
        out.push_back({mrpt::Clock::toDouble(mov->timestamp), pose.x(), pose.y(), pose.phi()});
    }
    return out;
}

}  // namespace hymm::datasets
