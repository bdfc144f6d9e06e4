#include "config_text.h"

#include <hymm/core/config_utils.h>

#include <charconv>

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

}  // namespace hymm::sim::detail
