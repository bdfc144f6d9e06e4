#include "hymm/core/config_utils.h"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/system/filesystem.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace hymm::core
{
std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) return {};
    const auto e = s.find_last_not_of(" \t\r\n");
    return s.substr(b, e - b + 1);
}

namespace
{

// MRPT returns the default when a key is absent; an empty marker tells us that.
bool rawValue(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    std::string& out)
{
    if (!cfg.keyExists(section, key)) return false;
    out = trim(cfg.read_string(section, key, "", false));
    return true;
}

[[noreturn]] void throwMissing(const std::string& section, const std::string& key)
{
    throw ConfigError("[" + section + "] required key '" + key + "' is missing", section, key);
}
}  // namespace

void throwConfigError(
    const std::string& section, const std::string& key, const std::string& value,
    const std::string& what)
{
    throw ConfigError("[" + section + "] " + key + "=" + value + ": " + what, section, key);
}

std::unique_ptr<mrpt::config::CConfigFileBase> openConfigFile(const std::string& path)
{
    if (path.empty()) throw std::invalid_argument("config file path is empty");
    if (!mrpt::system::fileExists(path))
        throw std::invalid_argument("config file not found: '" + path + "'");
    try
    {
        return std::make_unique<mrpt::config::CConfigFile>(path);
    }
    catch (const std::exception& e)
    {
        throw std::invalid_argument("cannot parse config file '" + path + "': " + e.what());
    }
}

void checkKnownKeys(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const std::vector<std::string>& known)
{
    std::vector<std::string> keys;
    cfg.getAllKeys(section, keys);
    for (const auto& k : keys)
    {
        if (std::find(known.begin(), known.end(), k) == known.end())
        {
            std::ostringstream ss;
            ss << "[" << section << "] unknown key '" << k << "' (known:";
            for (const auto& kk : known) ss << " " << kk;
            ss << ")";
            throw ConfigError(ss.str(), section, k);
        }
    }
}

double readDouble(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    double def, bool required)
{
    std::string v;
    if (!rawValue(cfg, section, key, v))
    {
        if (required) throwMissing(section, key);
        return def;
    }
    char* end = nullptr;
    errno = 0;
    const double d = std::strtod(v.c_str(), &end);
    if (v.empty() || end == v.c_str() || trim(end).size() != 0 || errno == ERANGE)
        throwConfigError(section, key, v, "not a number");
    if (!std::isfinite(d)) throwConfigError(section, key, v, "must be finite");
    return d;
}

double readDoubleMin(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    double def, double min_value, bool strict, bool required)
{
    const double d = readDouble(cfg, section, key, def, required);
    if (strict ? !(d > min_value) : !(d >= min_value))
    {
        std::ostringstream what;
        what << "must be " << (strict ? "> " : ">= ") << min_value;
        throwConfigError(section, key, std::to_string(d), what.str());
    }
    return d;
}

long readInt(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    long def, bool required)
{
    std::string v;
    if (!rawValue(cfg, section, key, v))
    {
        if (required) throwMissing(section, key);
        return def;
    }
    char* end = nullptr;
    errno = 0;
    const long i = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || end == v.c_str() || trim(end).size() != 0 || errno == ERANGE)
        throwConfigError(section, key, v, "not an integer");
    return i;
}

bool readBool(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    bool def, bool required)
{
    std::string v;
    if (!rawValue(cfg, section, key, v))
    {
        if (required) throwMissing(section, key);
        return def;
    }
    std::string l = v;
    std::transform(l.begin(), l.end(), l.begin(), ::tolower);
    if (l == "true" || l == "1" || l == "yes" || l == "on") return true;
    if (l == "false" || l == "0" || l == "no" || l == "off") return false;
    throwConfigError(section, key, v, "not a boolean (true/false)");
}

std::string readString(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    const std::string& def, bool required)
{
    std::string v;
    if (!rawValue(cfg, section, key, v))
    {
        if (required) throwMissing(section, key);
        return def;
    }
    return v;
}

std::vector<double> readDoubleList(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    const std::vector<double>& def, bool required)
{
    std::string v;
    if (!rawValue(cfg, section, key, v))
    {
        if (required) throwMissing(section, key);
        return def;
    }
    std::string s = v;
    std::replace(s.begin(), s.end(), ',', ' ');
    std::istringstream is(s);
    std::vector<double> out;
    std::string tok;
    while (is >> tok)
    {
        char* end = nullptr;
        const double d = std::strtod(tok.c_str(), &end);
        if (end == tok.c_str() || *end != '\0' || !std::isfinite(d))
            throwConfigError(section, key, v, "'" + tok + "' is not a number");
        out.push_back(d);
    }
    return out;
}

}  // namespace hymm::core
