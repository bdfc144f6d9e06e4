/**
 * @file OptionTable.h
 * @brief Each .ini key declared once (name, unit, default, range, doc), bound to a member.
 *
 * An options struct describes its keys in one function,
 *
 *     core::OptionTable Options::table() {
 *         core::OptionTable t;
 *         t.real("max_range_m", max_range_m, "m", core::above(0), "farthest return used");
 *         t.integer("window", window, "", 1, 1000, "steps kept");
 *         return t;
 *     }
 *
 * and the loader (unknown keys are errors, absent keys keep the member's value), the saver
 * and the README key table (markdown()) all come from it. The default shown in the table is
 * the member's value when the table is made from a default-constructed struct.
 *
 * Errors are core::ConfigError (a std::invalid_argument) and print the section, the key and
 * the value exactly as written in the file.
 */
#pragma once

#include <hymm/core/config_utils.h>
#include <mrpt/config/CConfigFileBase.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace hymm::core
{
/** Closed or open interval of a numeric key; bounds may be infinite. */
struct Range
{
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool lo_open = false;
    bool hi_open = false;

    bool contains(double v) const;
    /** "[0, 1)", "> 0", ">= 0", ... as shown in errors and README tables. */
    std::string text() const;
};
inline Range between(double lo, double hi) { return {lo, hi, false, false}; }  //!< [lo, hi]
inline Range above(double lo, double hi = std::numeric_limits<double>::infinity())
{
    return {lo, hi, true, false};  //!< (lo, hi]
}
inline Range atLeast(double lo, double hi = std::numeric_limits<double>::infinity())
{
    return {lo, hi, false, false};  //!< [lo, hi]
}
inline Range openInterval(double lo, double hi) { return {lo, hi, true, true}; }  //!< (lo, hi)
inline Range halfOpen(double lo, double hi) { return {lo, hi, false, true}; }     //!< [lo, hi)

/** One declared key. */
struct OptionKey
{
    std::string name;
    std::string unit;     //!< "m", "deg", "s", "" ...
    std::string range;    //!< human-readable admissible values
    std::string doc;
    /** Parses the value as written and stores it; throws ConfigError. */
    std::function<void(const std::string& section, const std::string& raw)> parse;
    /** The member's current value as it would be written in a file. */
    std::function<std::string()> format;
};

class OptionTable
{
public:
    /** A real number; `scale` converts the file's unit to the member's (e.g. deg -> rad:
     *  member = scale * value). Non-finite values are errors. */
    OptionTable& real(const std::string& name, double& member, const std::string& unit, Range range,
                      const std::string& doc, double scale = 1.0);
    /** A real number in degrees stored in radians, rounded as mrpt::DEG2RAD
     *  (member = value * pi / 180). */
    OptionTable& degrees(const std::string& name, double& member_rad, Range range_deg,
                         const std::string& doc);
    /** An integer within [lo, hi] (and within the member's type). */
    template <class I>
    OptionTable& integer(const std::string& name, I& member, const std::string& unit, long long lo,
                         long long hi, const std::string& doc)
    {
        static_assert(std::is_integral_v<I> && !std::is_same_v<I, bool>, "integer key");
        const long long tlo = std::is_signed_v<I> ? static_cast<long long>(std::numeric_limits<I>::min()) : 0;
        const long long thi = static_cast<unsigned long long>(std::numeric_limits<I>::max()) >
                                      static_cast<unsigned long long>(std::numeric_limits<long long>::max())
                                  ? std::numeric_limits<long long>::max()
                                  : static_cast<long long>(std::numeric_limits<I>::max());
        if (lo < tlo) lo = tlo;
        if (hi > thi) hi = thi;
        addInteger(
            name, unit, lo, hi, doc, [&member](long long v) { member = static_cast<I>(v); },
            [&member]() { return static_cast<long long>(member); });
        return *this;
    }
    /** A list of real numbers separated by spaces or commas, each finite and in `range`,
     *  at least `min_count` of them. */
    OptionTable& reals(const std::string& name, std::vector<double>& member, const std::string& unit,
                       Range range, size_t min_count, const std::string& doc);
    OptionTable& flag(const std::string& name, bool& member, const std::string& doc);
    OptionTable& text(const std::string& name, std::string& member, const std::string& doc,
                      const std::string& range = "text");
    /** One of a fixed set of words mapped to enum (or other) values. */
    template <class E>
    OptionTable& choice(const std::string& name, E& member, std::vector<std::pair<std::string, E>> words,
                        const std::string& doc)
    {
        std::string allowed;
        for (const auto& w : words) allowed += (allowed.empty() ? "" : " \\| ") + ("`" + w.first + "`");
        OptionKey k;
        k.name = name;
        k.range = allowed;
        k.doc = doc;
        k.parse = [&member, words, name](const std::string& s, const std::string& raw) {
            for (const auto& w : words)
                if (w.first == raw)
                {
                    member = w.second;
                    return;
                }
            std::string list;
            for (const auto& w : words) list += (list.empty() ? "" : ", ") + w.first;
            throwConfigError(s, name, raw, "must be one of " + list);
        };
        k.format = [&member, words]() {
            for (const auto& w : words)
                if (w.second == member) return w.first;
            return std::string("?");
        };
        return add(std::move(k));
    }
    /** A key with its own parser and formatter (lists, sets of words). */
    OptionTable& custom(OptionKey key);
    /** Appends the keys of another table (a nested struct sharing the section). */
    OptionTable& include(OptionTable other);

    /** Checks that `section` holds only declared keys (else ConfigError naming the key and
     *  listing the known ones), then parses every declared key that is present. */
    void load(const mrpt::config::CConfigFileBase& cfg, const std::string& section) const;
    /** Writes every declared key. */
    void save(mrpt::config::CConfigFileBase& cfg, const std::string& section) const;
    /** README key table: | key | unit | default | range | meaning |. */
    std::string markdown() const;

    const std::vector<OptionKey>& keys() const { return keys_; }
    std::vector<std::string> names() const;

private:
    OptionTable& add(OptionKey k);
    OptionTable& realConverted(const std::string& name, double& member, const std::string& unit, Range range,
                               const std::string& doc, std::function<double(double)> to_member,
                               std::function<double(double)> to_file);
    void addInteger(const std::string& name, const std::string& unit, long long lo, long long hi,
                    const std::string& doc, std::function<void(long long)> set,
                    std::function<long long()> get);
    std::vector<OptionKey> keys_;
};

/** Shortest text that reads back to exactly `v` (used by saver and README tables). */
std::string formatReal(double v);

}  // namespace hymm::core
