/**
 * @file config_text.h
 * @brief Private helpers of hymm::sim for reading number lists from, and writing
 *        numbers to, .ini sections and text files (15 significant digits).
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <mrpt/config/CConfigFileBase.h>

#include <functional>

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

/** An OptionTable key holding a list of numbers as written in a file (spaces or commas
 *  between them), in groups of `group`, at least `min_groups` groups, each finite and
 *  within [-limit, limit]: `set` receives the parsed numbers (and may
 *  check more, throwing core::ConfigError), `get` gives them back for saving (an empty
 *  list for an optional key that is not set). */
hymm::core::OptionKey groupsKey(
    const std::string& name, const std::string& unit, size_t group, size_t min_groups, double limit,
    const std::string& doc,
    std::function<void(const std::vector<double>&, const std::string& section, const std::string& raw)> set,
    std::function<std::vector<double>()> get);

/** Writes every key of `table` but those named in `skip` (optional keys that are not set:
 *  a scenario without them keeps its saved text). */
void saveTable(mrpt::config::CConfigFileBase& cfg, const std::string& section,
               const hymm::core::OptionTable& table, const std::vector<std::string>& skip);

}  // namespace hymm::sim::detail
