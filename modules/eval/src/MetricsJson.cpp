#include "hymm/eval/MetricsJson.h"
#include <hymm/core/output_files.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace hymm::eval
{
MetricsJson::Entry& MetricsJson::slot(const std::string& key)
{
    for (auto& e : entries_)
        if (e.key == key)
        {
            e = Entry{};
            e.key = key;
            return e;
        }
    entries_.push_back(Entry{});
    entries_.back().key = key;
    return entries_.back();
}

MetricsJson& MetricsJson::set(const std::string& key, double value)
{
    Entry& e = slot(key);
    e.kind = Kind::Number;
    e.num = value;
    return *this;
}

MetricsJson& MetricsJson::set(const std::string& key, long long value)
{
    Entry& e = slot(key);
    e.kind = Kind::Integer;
    e.integer = value;
    return *this;
}

MetricsJson& MetricsJson::set(const std::string& key, unsigned long long value)
{
    Entry& e = slot(key);
    e.kind = Kind::Unsigned;
    e.uinteger = value;
    return *this;
}

MetricsJson& MetricsJson::set(const std::string& key, int value)
{
    return set(key, static_cast<long long>(value));
}
MetricsJson& MetricsJson::set(const std::string& key, long value)
{
    return set(key, static_cast<long long>(value));
}
MetricsJson& MetricsJson::set(const std::string& key, unsigned value)
{
    return set(key, static_cast<unsigned long long>(value));
}
MetricsJson& MetricsJson::set(const std::string& key, unsigned long value)
{
    return set(key, static_cast<unsigned long long>(value));
}

MetricsJson& MetricsJson::set(const std::string& key, bool value)
{
    Entry& e = slot(key);
    e.kind = Kind::Bool;
    e.flag = value;
    return *this;
}

MetricsJson& MetricsJson::set(const std::string& key, const std::string& value)
{
    Entry& e = slot(key);
    e.kind = Kind::String;
    e.str = value;
    return *this;
}

MetricsJson& MetricsJson::set(const std::string& key, const char* value)
{
    return set(key, std::string(value ? value : ""));
}

MetricsJson& MetricsJson::set(const std::string& key, const std::vector<double>& values)
{
    Entry& e = slot(key);
    e.kind = Kind::Numbers;
    e.nums = values;
    return *this;
}

MetricsJson& MetricsJson::set(const std::string& key, const std::vector<std::string>& values)
{
    Entry& e = slot(key);
    e.kind = Kind::Strings;
    e.strs = values;
    return *this;
}

MetricsJson& MetricsJson::setNull(const std::string& key)
{
    slot(key).kind = Kind::Null;
    return *this;
}

MetricsJson& MetricsJson::object(const std::string& key)
{
    for (auto& e : entries_)
        if (e.key == key && e.kind == Kind::Object) return e.obj.front();
    Entry& e = slot(key);
    e.kind = Kind::Object;
    e.obj.resize(1);
    return e.obj.front();
}

bool MetricsJson::has(const std::string& key) const
{
    for (const auto& e : entries_)
        if (e.key == key) return true;
    return false;
}

std::string MetricsJson::quote(const std::string& s)
{
    std::string out = "\"";
    for (const char ch : s)
    {
        const auto c = static_cast<unsigned char>(ch);
        switch (c)
        {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\b': out += "\\b"; break;
            case '\f': out += "\\f"; break;
            case '\n': out += "\\n"; break;
            case '\r': out += "\\r"; break;
            case '\t': out += "\\t"; break;
            default:
                if (c < 0x20)
                {
                    char buf[8];
                    std::snprintf(buf, sizeof(buf), "\\u%04x", static_cast<unsigned>(c));
                    out += buf;
                }
                else
                    out += ch;
        }
    }
    out += '"';
    return out;
}

std::string MetricsJson::number(double v)
{
    if (!std::isfinite(v)) return "null";
    char buf[64];
    const auto res = std::to_chars(buf, buf + sizeof(buf), v);  // shortest round-trip form
    return std::string(buf, res.ptr);
}

void MetricsJson::dumpTo(std::string& out, int indent, int level) const
{
    if (entries_.empty())
    {
        out += "{}";
        return;
    }
    const std::string nl = indent > 0 ? "\n" : "";
    const std::string pad(static_cast<size_t>(indent * (level + 1)), ' ');
    const std::string pad_end(static_cast<size_t>(indent * level), ' ');
    const std::string sep = indent > 0 ? ": " : ":";
    const std::string item_sep = indent > 0 ? ", " : ",";
    out += "{" + nl;
    for (size_t k = 0; k < entries_.size(); ++k)
    {
        const Entry& e = entries_[k];
        out += pad + quote(e.key) + sep;
        switch (e.kind)
        {
            case Kind::Null: out += "null"; break;
            case Kind::Number: out += number(e.num); break;
            case Kind::Integer: out += std::to_string(e.integer); break;
            case Kind::Unsigned: out += std::to_string(e.uinteger); break;
            case Kind::Bool: out += e.flag ? "true" : "false"; break;
            case Kind::String: out += quote(e.str); break;
            case Kind::Numbers:
                out += "[";
                for (size_t i = 0; i < e.nums.size(); ++i)
                    out += (i ? item_sep : "") + number(e.nums[i]);
                out += "]";
                break;
            case Kind::Strings:
                out += "[";
                for (size_t i = 0; i < e.strs.size(); ++i)
                    out += (i ? item_sep : "") + quote(e.strs[i]);
                out += "]";
                break;
            case Kind::Object: e.obj.front().dumpTo(out, indent, level + 1); break;
        }
        out += (k + 1 < entries_.size() ? "," : "") + nl;
    }
    out += pad_end + "}";
}

std::string MetricsJson::dump(int indent) const
{
    std::string out;
    dumpTo(out, indent < 0 ? 0 : indent, 0);
    return out;
}

void MetricsJson::save(const std::string& path, int indent) const
{
    core::writeFileAtomically(path, dump(indent) + '\n');
}

}  // namespace hymm::eval
