/**
 * @file MetricsJson.h
 * @brief A small JSON object writer for run metrics (no third-party JSON dependency).
 *
 * Holds an ordered object of keys mapped to numbers, integers, booleans, strings, arrays of
 * numbers or strings, and nested objects. Keys keep their first insertion order; setting
 * an existing key replaces its value in place. Output is standard JSON (RFC 8259):
 * strings are escaped (quote, backslash, control characters; bytes >= 0x80 pass through as
 * UTF-8), doubles are written in the shortest form that reads back to the same value, and
 * non-finite doubles (NaN, inf), which JSON cannot represent, are written as null.
 */
#pragma once

#include <string>
#include <vector>

namespace hymm::eval
{
class MetricsJson
{
public:
    MetricsJson& set(const std::string& key, double value);
    MetricsJson& set(const std::string& key, int value);
    MetricsJson& set(const std::string& key, long value);
    MetricsJson& set(const std::string& key, long long value);
    MetricsJson& set(const std::string& key, unsigned value);
    MetricsJson& set(const std::string& key, unsigned long value);
    MetricsJson& set(const std::string& key, unsigned long long value);
    MetricsJson& set(const std::string& key, bool value);
    MetricsJson& set(const std::string& key, const std::string& value);
    MetricsJson& set(const std::string& key, const char* value);
    MetricsJson& set(const std::string& key, const std::vector<double>& values);
    MetricsJson& set(const std::string& key, const std::vector<std::string>& values);
    MetricsJson& setNull(const std::string& key);

    /** The nested object under `key`, created empty if absent (replacing a non-object). */
    MetricsJson& object(const std::string& key);

    bool has(const std::string& key) const;
    size_t size() const { return entries_.size(); }

    /** Serialises the object; `indent` spaces per level (0: a single line). */
    std::string dump(int indent = 2) const;

    /** Writes dump() plus a newline to `path`; throws std::runtime_error naming the path. */
    void save(const std::string& path, int indent = 2) const;

    /** `s` as a quoted JSON string literal. */
    static std::string quote(const std::string& s);
    /** `v` as a JSON number, or "null" if not finite. */
    static std::string number(double v);

private:
    enum class Kind
    {
        Null,
        Number,
        Integer,
        Unsigned,
        Bool,
        String,
        Numbers,
        Strings,
        Object
    };
    struct Entry
    {
        std::string key;
        Kind kind = Kind::Null;
        double num = 0;
        long long integer = 0;
        unsigned long long uinteger = 0;
        bool flag = false;
        std::string str;
        std::vector<double> nums;
        std::vector<std::string> strs;
        std::vector<MetricsJson> obj;  //!< exactly one element when kind == Object
    };

    Entry& slot(const std::string& key);
    void dumpTo(std::string& out, int indent, int level) const;

    std::vector<Entry> entries_;
};

}  // namespace hymm::eval
