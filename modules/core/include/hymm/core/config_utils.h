/**
 * @file config_utils.h
 * @brief Strict loading of MRPT-style .ini configuration (STYLE.md rule 8).
 *
 * Every options struct in HYMM loads through these helpers so that a typo in an
 * .ini key, a missing file, a non-numeric value or an out-of-range number gives a
 * clear error naming the section, key, value and path instead of a silent default.
 */
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace hymm::core
{
/** A bad config value or key; `section` and `key` let a file-level loader add the line. */
struct ConfigError : public std::invalid_argument
{
    ConfigError(const std::string& what, std::string section_, std::string key_)
        : std::invalid_argument(what), section(std::move(section_)), key(std::move(key_))
    {
    }
    std::string section;
    std::string key;  //!< empty for errors about a whole section
};

/** Opens an .ini file for reading; throws if the file does not exist or cannot be
 *  parsed. The returned object keeps the path for error messages. */
std::unique_ptr<mrpt::config::CConfigFileBase> openConfigFile(const std::string& path);

/** Throws if `section` holds a key that is not in `known` (unknown keys are typos). */
void checkKnownKeys(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const std::vector<std::string>& known);

/** Reads a double; throws if the key is present but not a number. Returns `def`
 *  when absent, or throws when absent and `required`. */
double readDouble(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    double def, bool required = false);

/** As readDouble, then checks `value >= min_value` (or `> min_value` if strict). */
double readDoubleMin(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    double def, double min_value, bool strict, bool required = false);

/** Reads an integer; throws if present but not an integer. */
long readInt(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    long def, bool required = false);

/** Reads a boolean (true/false/1/0/yes/no); throws on anything else. */
bool readBool(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    bool def, bool required = false);

/** Reads a string; throws if absent and `required`. */
std::string readString(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    const std::string& def, bool required = false);

/** Reads a whitespace/comma separated list of numbers. */
std::vector<double> readDoubleList(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    const std::vector<double>& def, bool required = false);

/** `s` without leading and trailing blanks (space, tab, CR, LF). */
std::string trim(const std::string& s);

/** Throws a ConfigError "[section] key=value: what". */
[[noreturn]] void throwConfigError(
    const std::string& section, const std::string& key, const std::string& value,
    const std::string& what);

}  // namespace hymm::core
