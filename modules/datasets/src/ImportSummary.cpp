#include "hymm/datasets/ImportSummary.h"

#include <iomanip>
#include <sstream>

namespace hymm::datasets
{
size_t ImportSummary::skippedCount(const std::string& reason) const
{
    const auto it = skipped.find(reason);
    return it == skipped.end() ? 0 : it->second;
}

size_t ImportSummary::repairedCount(const std::string& reason) const
{
    const auto it = repaired.find(reason);
    return it == repaired.end() ? 0 : it->second;
}

std::string ImportSummary::toString() const
{
    std::ostringstream s;
    s << std::fixed << std::setprecision(3);
    s << "format:              " << format << "\n"
      << "frames:              " << frames << "\n"
      << "observations:        " << observations << "\n"
      << "measurements:        " << measurements << "\n"
      << "odometry samples:    " << odometry_samples << "\n"
      << "odometry gaps [s]:   " << odometry_gap_s << "\n"
      << "time span [s]:       " << first_time_s << " .. " << last_time_s << "\n"
      << "ground-truth poses:  " << ground_truth_poses << "\n"
      << "landmarks:           " << landmarks << "\n";
    if (skipped.empty()) s << "skipped:             none\n";
    for (const auto& [reason, n] : skipped) s << "skipped " << reason << ": " << n << "\n";
    for (const auto& [reason, n] : repaired) s << "repaired " << reason << ": " << n << "\n";
    for (const auto& o : outputs) s << "wrote " << o << "\n";
    return s.str();
}

}  // namespace hymm::datasets
