#include "hymm/core/StrictConfigFile.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "hymm/core/config_utils.h"

namespace hymm::core
{
namespace
{

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

[[noreturn]] void fail(const std::string& file, int line, const std::string& what,
                       const std::string& section = "", const std::string& key = "")
{
    throw ConfigError(
        "config file '" + file + "'" + (line > 0 ? " line " + std::to_string(line) : "") + ": " + what,
        section, key);
}

/** Throws, naming the line, at the first control byte of `text` other than tab and
 *  line ends (an .ini is text). */
void rejectBinary(const std::string& text, const std::string& name)
{
    int byte_line = 1;
    for (unsigned char c : text)
    {
        if (c == '\n')
            ++byte_line;
        else if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7f)
        {
            std::ostringstream h;
            h << std::hex << static_cast<unsigned>(c);
            fail(name, byte_line, "binary content (byte 0x" + h.str() + "), not an .ini text");
        }
    }
}
}  // namespace

/** Forwards to MRPT's parsed content and records which sections loaders asked about. */
class StrictConfigFile::Tracking : public mrpt::config::CConfigFileBase
{
public:
    explicit Tracking(const std::string& text) : mem_(text) {}
    void getAllSections(std::vector<std::string>& sections) const override
    {
        mem_.getAllSections(sections);
    }
    void getAllKeys(const std::string& section, std::vector<std::string>& keys) const override
    {
        used_.insert(section);
        mem_.getAllKeys(section, keys);
    }
    void clear() override { mem_.clear(); }
    bool used(const std::string& section) const { return used_.count(section) > 0; }

protected:
    void writeString(const std::string& section, const std::string& name, const std::string& str) override
    {
        mem_.write(section, name, str);
    }
    std::string readString(const std::string& section, const std::string& name, const std::string& def,
                           bool fail_if_not_found) const override
    {
        used_.insert(section);
        return mem_.read_string(section, name, def, fail_if_not_found);
    }

private:
    mrpt::config::CConfigFileMemory mem_;
    mutable std::set<std::string> used_;
};

StrictConfigFile::StrictConfigFile(const std::string& path)
{
    if (path.empty()) throw ConfigError("config file path is empty", "", "");
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(path, 0, "cannot be opened for reading (missing or not readable)");
    std::ostringstream ss;
    ss << f.rdbuf();
    if (f.bad()) fail(path, 0, "read error");
    *this = StrictConfigFile(ss.str(), path, true);
}

StrictConfigFile StrictConfigFile::fromText(const std::string& text, const std::string& name)
{
    return StrictConfigFile(text, name, true);
}

StrictConfigFile::StrictConfigFile(StrictConfigFile&&) noexcept = default;
StrictConfigFile& StrictConfigFile::operator=(StrictConfigFile&&) noexcept = default;
StrictConfigFile::~StrictConfigFile() = default;

StrictConfigFile::StrictConfigFile(const std::string& text, const std::string& name, bool) : path_(name)
{
    std::istringstream is(text);
    std::string raw;
    int line = 0;
    std::string section;
    int section_line = 0;
    size_t section_keys = 0;
    std::set<std::string> seen_sections;
    std::set<std::string> seen_keys;
    const auto closeSection = [&]() {
        if (!section.empty() && section_keys == 0)
            fail(name, section_line, "section [" + section + "] holds no key", section);
    };
    // Binary content first: garbage must not be reported as a malformed line.
    rejectBinary(text, name);
    while (std::getline(is, raw))
    {
        ++line;
        const std::string l = trim(raw);
        if (l.empty() || l[0] == ';' || l[0] == '#') continue;
        if (l[0] == '[')
        {
            const auto close = l.find(']');
            const std::string s = close == std::string::npos ? "" : trim(l.substr(1, close - 1));
            if (close == std::string::npos || s.empty() || !trim(l.substr(close + 1)).empty())
                fail(name, line, "malformed section header '" + l + "'");
            closeSection();
            if (!seen_sections.insert(lower(s)).second)
                fail(name, line, "duplicate section [" + s + "] (first at line " +
                                     std::to_string(lineOf(s)) + ")", s);
            section = s;
            section_line = line;
            section_keys = 0;
            seen_keys.clear();
            sections_.emplace_back(s, line);
            continue;
        }
        const auto eq = l.find('=');
        if (eq == std::string::npos) fail(name, line, "not a 'key = value' line: '" + l + "'");
        const std::string key = trim(l.substr(0, eq));
        if (key.empty()) fail(name, line, "key name missing: '" + l + "'");
        if (section.empty()) fail(name, line, "key '" + key + "' is outside any [section]", "", key);
        if (!seen_keys.insert(lower(key)).second)
            fail(name, line, "duplicate key '" + key + "' in [" + section + "] (first at line " +
                                 std::to_string(lineOf(section, key)) + ")", section, key);
        ++section_keys;
        lines_[{section, key}] = line;
    }
    closeSection();
    if (sections_.empty()) fail(name, 0, "holds no [section] (empty or comments only)");
    cfg_ = std::make_unique<Tracking>(text);
}

const mrpt::config::CConfigFileBase& StrictConfigFile::config() const { return *cfg_; }

int StrictConfigFile::lineOf(const std::string& section, const std::string& key) const
{
    if (key.empty())
    {
        for (const auto& [s, l] : sections_)
            if (lower(s) == lower(section)) return l;
        return 0;
    }
    for (const auto& [sk, l] : lines_)
        if (lower(sk.first) == lower(section) && lower(sk.second) == lower(key)) return l;
    return 0;
}

void StrictConfigFile::load(const std::function<void(const mrpt::config::CConfigFileBase&)>& loader) const
{
    try
    {
        loader(config());
    }
    catch (const ConfigError& e)
    {
        int line = lineOf(e.section, e.key);
        if (line == 0) line = lineOf(e.section);
        fail(path_, line, e.what(), e.section, e.key);
    }
}

void StrictConfigFile::checkAllSectionsKnown() const
{
    for (const auto& [s, l] : sections_)
        if (!cfg_->used(s))
            fail(path_, l, "unknown section [" + s + "] (no loader of this program reads it)", s);
}

}  // namespace hymm::core
