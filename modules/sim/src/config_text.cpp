#include "config_text.h"

#include <hymm/core/config_utils.h>

#include <charconv>
#include <memory>

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

namespace
{
/** Throws unless `count` numbers make at least `min_groups` whole groups of `group`. */
void checkGroups(const std::string& section, const std::string& key, const std::string& shown,
                 size_t count, size_t group, size_t min_groups)
{
    if (count % group != 0 || count < group * min_groups)
        hymm::core::throwConfigError(
            section, key, shown,
            "expected " + (min_groups > 1 ? "at least " + std::to_string(min_groups) + " " : "") +
                "group(s) of " + std::to_string(group) + " numbers");
}
}  // namespace

std::vector<double> readGroups(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                               const std::string& key, size_t group, size_t min_groups,
                               bool required)
{
    const auto v = hymm::core::readDoubleList(cfg, section, key, {}, required);
    if (!cfg.keyExists(section, key)) return v;
    checkGroups(section, key, formatNumbers(v), v.size(), group, min_groups);
    return v;
}

hymm::core::OptionKey groupsKey(
    const std::string& name, const std::string& unit, size_t group, size_t min_groups, double limit,
    const std::string& doc,
    std::function<void(const std::vector<double>&, const std::string& section, const std::string& raw)> set,
    std::function<std::vector<double>()> get)
{
    // The numbers are parsed by OptionTable's own list key (separators, finiteness, range,
    // errors with the value as written) into a buffer this key owns; the grouping and the
    // member's shape are checked here.
    auto numbers = std::make_shared<std::vector<double>>();
    hymm::core::OptionTable list;
    list.reals(name, *numbers, unit, hymm::core::between(-limit, limit), 0, doc);
    hymm::core::OptionKey k = list.keys().front();
    const std::string each = "each in [-" + formatNumber(limit) + ", " + formatNumber(limit) + "]";
    k.range = group == 1 ? "numbers, " + each
                         : (min_groups > 1 ? std::to_string(min_groups) + "+ " : std::string()) + "groups of " +
                               std::to_string(group) + " numbers, " + each;
    k.parse = [parse = k.parse, numbers, name, group, min_groups, set](const std::string& s, const std::string& raw) {
        parse(s, raw);
        checkGroups(s, name, raw, numbers->size(), group, min_groups);
        set(*numbers, s, raw);
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
