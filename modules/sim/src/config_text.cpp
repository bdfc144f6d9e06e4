#include "config_text.h"

#include <hymm/core/config_utils.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace hymm::sim::detail
{
std::string formatNumber(double v)
{
    // 15 significant digits: what a person typed reads back unchanged, and so does a
    // degree value that went through radians (no 29.999999999999996).
    constexpr int kDigits = 15;
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::general, kDigits);
    return std::string(buf, r.ptr);
}

std::string formatNumbers(const std::vector<double>& v)
{
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i ? " " : "") + formatNumber(v[i]);
    return s;
}

void writeNumber(mrpt::config::CConfigFileBase& cfg, const std::string& section,
                 const std::string& key, double v)
{
    cfg.write(section, key, formatNumber(v));
}

void writeNumbers(mrpt::config::CConfigFileBase& cfg, const std::string& section,
                  const std::string& key, const std::vector<double>& v)
{
    cfg.write(section, key, formatNumbers(v));
}

std::vector<double> readGroups(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                               const std::string& key, size_t group, size_t min_groups,
                               bool required)
{
    const auto v = hymm::core::readDoubleList(cfg, section, key, {}, required);
    if (!cfg.keyExists(section, key)) return v;
    if (v.size() % group != 0 || v.size() < group * min_groups)
        hymm::core::throwConfigError(
            section, key, formatNumbers(v),
            "expected " + (min_groups > 1 ? "at least " + std::to_string(min_groups) + " " : "") +
                "group(s) of " + std::to_string(group) + " numbers");
    return v;
}

std::vector<double> parseGroups(const std::string& section, const std::string& key,
                                const std::string& raw, size_t group, size_t min_groups,
                                double limit)
{
    std::string text = raw;
    std::replace(text.begin(), text.end(), ',', ' ');
    std::istringstream is(text);
    std::vector<double> out;
    for (std::string tok; is >> tok;)
    {
        char* end = nullptr;
        errno = 0;
        const double d = std::strtod(tok.c_str(), &end);
        if (end == tok.c_str() || *end != '\0' || errno == ERANGE)
            hymm::core::throwConfigError(section, key, raw, "'" + tok + "' is not a number");
        if (!std::isfinite(d) || std::abs(d) > limit)
            hymm::core::throwConfigError(section, key, raw,
                                         "'" + tok + "' out of range, must be in [-" +
                                             formatNumber(limit) + ", " + formatNumber(limit) + "]");
        out.push_back(d);
    }
    if (out.size() % group != 0 || out.size() < group * min_groups)
        hymm::core::throwConfigError(
            section, key, raw,
            "expected " + (min_groups > 1 ? "at least " + std::to_string(min_groups) + " " : "") +
                "group(s) of " + std::to_string(group) + " numbers");
    return out;
}

hymm::core::OptionKey groupsKey(
    const std::string& name, const std::string& unit, size_t group, size_t min_groups, double limit,
    const std::string& doc,
    std::function<void(const std::vector<double>&, const std::string& section, const std::string& raw)> set,
    std::function<std::vector<double>()> get)
{
    hymm::core::OptionKey k;
    k.name = name;
    k.unit = unit;
    const std::string each = "each in [-" + formatNumber(limit) + ", " + formatNumber(limit) + "]";
    k.range = group == 1 ? "numbers, " + each
                         : (min_groups > 1 ? std::to_string(min_groups) + "+ " : std::string()) + "groups of " +
                               std::to_string(group) + " numbers, " + each;
    k.doc = doc;
    k.parse = [name, group, min_groups, limit, set](const std::string& s, const std::string& raw) {
        set(parseGroups(s, name, raw, group, min_groups, limit), s, raw);
    };
    k.format = [get]() { return formatNumbers(get()); };
    return k;
}

void saveTable(mrpt::config::CConfigFileBase& cfg, const std::string& section,
               const hymm::core::OptionTable& table, const std::vector<std::string>& skip)
{
    for (const auto& k : table.keys())
        if (std::find(skip.begin(), skip.end(), k.name) == skip.end())
            cfg.write(section, k.name, k.format());
}

}  // namespace hymm::sim::detail
