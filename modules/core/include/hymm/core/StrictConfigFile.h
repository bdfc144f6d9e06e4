/**
 * @file StrictConfigFile.h
 * @brief An .ini file read strictly: what MRPT would silently accept is an error here.
 *
 * On opening, a pre-scan of the text rejects, naming the file and line: an unreadable,
 * empty or comments-only file, binary content (NUL or control bytes), a key outside any
 * section, a line that is neither `[section]`, `key = value` nor a comment (`;` or `#`),
 * a duplicate section, a duplicate key within a section (MRPT's parser keeps one silently),
 * and a section with no key. The content is then parsed by MRPT (CConfigFileMemory).
 *
 * Loaders read through config(), which records every section a loader asked about; after
 * loading, checkAllSectionsKnown() rejects a section no loader knows (a misspelt
 * `[EkfSlamm]`). load() runs a loader and adds the file name and line to its ConfigError.
 */
#pragma once

#include <hymm/core/config_utils.h>
#include <mrpt/config/CConfigFileBase.h>

#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>

namespace hymm::core
{
class StrictConfigFile
{
public:
    /** Reads and pre-scans `path`; throws ConfigError naming the file (and line). */
    explicit StrictConfigFile(const std::string& path);
    /** The same checks on text in memory; `name` stands for the file in messages. */
    static StrictConfigFile fromText(const std::string& text, const std::string& name);

    StrictConfigFile(StrictConfigFile&&) noexcept;
    StrictConfigFile& operator=(StrictConfigFile&&) noexcept;
    ~StrictConfigFile();

    /** The parsed content; reading a section through it marks the section as known. */
    const mrpt::config::CConfigFileBase& config() const;
    const std::string& path() const { return path_; }

    /** Runs `loader(config())`; a ConfigError it throws gets "file:line: " in front. */
    void load(const std::function<void(const mrpt::config::CConfigFileBase&)>& loader) const;
    /** Throws ConfigError for the first section (in file order) that no loader read. */
    void checkAllSectionsKnown() const;

    /** Line of `[section]` (1-based), or of `key` in it; 0 if unknown. */
    int lineOf(const std::string& section, const std::string& key = "") const;

private:
    StrictConfigFile(const std::string& text, const std::string& name, bool);
    class Tracking;
    std::string path_;
    std::unique_ptr<Tracking> cfg_;
    std::vector<std::pair<std::string, int>> sections_;         //!< file order, line
    std::map<std::pair<std::string, std::string>, int> lines_;  //!< (section, key) -> line
};

}  // namespace hymm::core
