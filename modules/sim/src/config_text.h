/**
 * @file config_text.h
 * @brief Private helpers of hymm::sim for reading number lists from, and writing
 *        numbers to, .ini sections and text files (15 significant digits).
 */
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <string>
#include <vector>

namespace hymm::sim::detail
{
std::string formatNumber(double v);
std::string formatNumbers(const std::vector<double>& v);

void writeNumber(mrpt::config::CConfigFileBase& cfg, const std::string& section,
                 const std::string& key, double v);
void writeNumbers(mrpt::config::CConfigFileBase& cfg, const std::string& section,
                  const std::string& key, const std::vector<double>& v);

/** A list of numbers read in groups of `group` (e.g. x y pairs); throws naming the key if
 *  the count is not a multiple of `group` or is below `min_groups` groups. Returns an
 *  empty list when the key is absent and not required. */
std::vector<double> readGroups(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                               const std::string& key, size_t group, size_t min_groups,
                               bool required = false);

}  // namespace hymm::sim::detail
