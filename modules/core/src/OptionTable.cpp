#include "hymm/core/OptionTable.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "hymm/core/config_utils.h"

namespace hymm::core
{
namespace
{

std::string num(double v)
{
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    return formatReal(v);
}
}  // namespace

std::string formatReal(double v)
{
    // The shortest of %.15g..%.17g that reads back exactly: 0.1 stays "0.1".
    for (int prec = 15; prec <= 17; ++prec)
    {
        std::ostringstream os;
        os.precision(prec);
        os << v;
        if (std::strtod(os.str().c_str(), nullptr) == v || prec == 17) return os.str();
    }
    return {};
}

bool Range::contains(double v) const
{
    const bool lo_ok = lo_open ? v > lo : v >= lo;
    const bool hi_ok = hi_open ? v < hi : v <= hi;
    return lo_ok && hi_ok;
}

std::string Range::text() const
{
    const bool no_lo = std::isinf(lo) && lo < 0;
    const bool no_hi = std::isinf(hi) && hi > 0;
    if (no_lo && no_hi) return "any";
    if (no_hi) return (lo_open ? "> " : ">= ") + num(lo);
    if (no_lo) return (hi_open ? "< " : "<= ") + num(hi);
    return (lo_open ? "(" : "[") + num(lo) + ", " + num(hi) + (hi_open ? ")" : "]");
}

OptionTable& OptionTable::add(OptionKey k)
{
    for (const auto& e : keys_)
        if (e.name == k.name) throw std::logic_error("option key '" + k.name + "' declared twice");
    keys_.push_back(std::move(k));
    return *this;
}

OptionTable& OptionTable::custom(OptionKey key) { return add(std::move(key)); }

OptionTable& OptionTable::include(OptionTable other)
{
    for (auto& k : other.keys_) add(std::move(k));
    return *this;
}

OptionTable& OptionTable::real(const std::string& name, double& member, const std::string& unit,
                               Range range, const std::string& doc, double scale)
{
    if (scale == 1.0) return realConverted(name, member, unit, range, doc, nullptr, nullptr);
    return realConverted(
        name, member, unit, range, doc, [scale](double v) { return scale * v; },
        [scale](double m) { return m / scale; });
}

OptionTable& OptionTable::realConverted(const std::string& name, double& member, const std::string& unit,
                                        Range range, const std::string& doc,
                                        std::function<double(double)> to_member,
                                        std::function<double(double)> to_file)
{
    OptionKey k;
    k.name = name;
    k.unit = unit;
    k.range = range.text();
    k.doc = doc;
    k.parse = [&member, range, name, to_member](const std::string& s, const std::string& raw) {
        char* end = nullptr;
        errno = 0;
        const double d = std::strtod(raw.c_str(), &end);
        if (raw.empty() || end == raw.c_str() || !trim(end).empty() || errno == ERANGE)
            throwConfigError(s, name, raw, "not a number");
        if (!std::isfinite(d)) throwConfigError(s, name, raw, "must be finite");
        if (!range.contains(d)) throwConfigError(s, name, raw, "out of range, must be " + range.text());
        member = to_member ? to_member(d) : d;
    };
    k.format = [&member, to_file, to_member]() {
        if (!to_file) return formatReal(member);
        // The shortest text that reads back to the member through the conversion: a
        // value given as 30 deg is written as 30, not 29.999999999999996.
        const double v = to_file(member);
        for (int prec = 15; prec < 17; ++prec)
        {
            std::ostringstream os;
            os.precision(prec);
            os << v;
            if (to_member(std::strtod(os.str().c_str(), nullptr)) == member) return os.str();
        }
        return formatReal(v);
    };
    return add(std::move(k));
}

OptionTable& OptionTable::degrees(const std::string& name, double& member_rad, Range range_deg,
                                  const std::string& doc)
{
    // mrpt::DEG2RAD's rounding (x * pi / 180), so values stay bit-identical to MRPT's.
    return realConverted(
        name, member_rad, "deg", range_deg, doc, [](double v) { return v * M_PI / 180.0; },
        [](double m) { return m * 180.0 / M_PI; });
}

void OptionTable::addInteger(const std::string& name, const std::string& unit, long long lo,
                             long long hi, const std::string& doc, std::function<void(long long)> set,
                             std::function<long long()> get)
{
    OptionKey k;
    k.name = name;
    k.unit = unit;
    const bool no_hi = hi == std::numeric_limits<long long>::max() ||
                       hi == std::numeric_limits<int>::max() || hi == std::numeric_limits<long>::max();
    k.range = no_hi ? "integer >= " + std::to_string(lo)
                    : "integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    k.doc = doc;
    const std::string range_text = k.range;
    k.parse = [set, lo, hi, name, range_text](const std::string& s, const std::string& raw) {
        char* end = nullptr;
        errno = 0;
        const long long v = std::strtoll(raw.c_str(), &end, 10);
        if (raw.empty() || end == raw.c_str() || !trim(end).empty())
            throwConfigError(s, name, raw, "not an integer");
        if (errno == ERANGE || v < lo || v > hi)
            throwConfigError(s, name, raw, "out of range, must be " + range_text);
        set(v);
    };
    k.format = [get]() { return std::to_string(get()); };
    add(std::move(k));
}

OptionTable& OptionTable::reals(const std::string& name, std::vector<double>& member,
                                const std::string& unit, Range range, size_t min_count,
                                const std::string& doc)
{
    OptionKey k;
    k.name = name;
    k.unit = unit;
    k.range = (min_count > 1 ? std::to_string(min_count) + "+" : std::string(min_count ? "1+" : "0+")) +
              " numbers, each " + range.text();
    k.doc = doc;
    k.parse = [&member, range, name, min_count](const std::string& s, const std::string& raw) {
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
                throwConfigError(s, name, raw, "'" + tok + "' is not a number");
            if (!std::isfinite(d)) throwConfigError(s, name, raw, "'" + tok + "' is not finite");
            if (!range.contains(d))
                throwConfigError(s, name, raw, "'" + tok + "' out of range, must be " + range.text());
            out.push_back(d);
        }
        if (out.size() < min_count)
            throwConfigError(s, name, raw, "needs at least " + std::to_string(min_count) + " numbers");
        member = out;
    };
    k.format = [&member]() {
        std::string out;
        for (double v : member) out += (out.empty() ? "" : " ") + formatReal(v);
        return out;
    };
    return add(std::move(k));
}

OptionTable& OptionTable::flag(const std::string& name, bool& member, const std::string& doc)
{
    OptionKey k;
    k.name = name;
    k.range = "`true` \\| `false`";
    k.doc = doc;
    k.parse = [&member, name](const std::string& s, const std::string& raw) {
        std::string l = raw;
        std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return std::tolower(c); });
        if (l == "true" || l == "1" || l == "yes" || l == "on")
            member = true;
        else if (l == "false" || l == "0" || l == "no" || l == "off")
            member = false;
        else
            throwConfigError(s, name, raw, "not a boolean (true/false)");
    };
    k.format = [&member]() { return std::string(member ? "true" : "false"); };
    return add(std::move(k));
}

OptionTable& OptionTable::text(const std::string& name, std::string& member, const std::string& doc,
                               const std::string& range)
{
    OptionKey k;
    k.name = name;
    k.range = range;
    k.doc = doc;
    k.parse = [&member](const std::string&, const std::string& raw) { member = raw; };
    k.format = [&member]() { return member; };
    return add(std::move(k));
}

std::vector<std::string> OptionTable::names() const
{
    std::vector<std::string> out;
    for (const auto& k : keys_) out.push_back(k.name);
    return out;
}

void OptionTable::load(const mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    checkKnownKeys(cfg, section, names());
    for (const auto& k : keys_)
    {
        if (!cfg.keyExists(section, k.name)) continue;
        k.parse(section, trim(cfg.read_string(section, k.name, "", false)));
    }
}

void OptionTable::save(mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    for (const auto& k : keys_) cfg.write(section, k.name, k.format());
}

std::string OptionTable::markdown() const
{
    std::ostringstream os;
    os << "| key | unit | default | range | meaning |\n|---|---|---|---|---|\n";
    for (const auto& k : keys_)
    {
        const std::string def = k.format();
        os << "| `" << k.name << "` | " << k.unit << " | " << (def.empty() ? "(empty)" : "`" + def + "`")
           << " | " << k.range << " | " << k.doc << " |\n";
    }
    return os.str();
}

}  // namespace hymm::core
