/**
 * @file slam_config.h
 * @brief hymm-slam's configuration read strictly, and the list of every options section.
 *
 * loadSlamConfig() reads the .ini through core::StrictConfigFile: an unreadable, empty,
 * comments-only or binary file, a duplicate key or section, a section with no key and a
 * section that no loader of hymm-slam reads are errors naming the file and line; every
 * key is range-checked by its declaration (core::OptionTable).
 *
 * optionSections() lists every options section hymm-slam and hymm-simul read, with its
 * module and its declaration table: the README key tables are generated from it
 * (`hymm-options-doc`, checked by the test `options_readme_tables`).
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <hymm/core/StrictConfigFile.h>
#include <hymm/denseslam/DenseSlam.h>

#include <functional>
#include <string>
#include <vector>

namespace hymm::app
{
/** DenseSlam::fromConfig over a strictly read file; throws core::ConfigError. */
denseslam::DenseSlam loadSlamConfig(const std::string& path);
/** As above on an opened file (kept open to run several times, e.g. per seed). */
denseslam::DenseSlam loadSlamConfig(const core::StrictConfigFile& file);

struct OptionSection
{
    std::string module;   //!< modules/<module>/README.md holds its table
    std::string section;  //!< ini section name
    /** Declaration table of a default-constructed options struct (defaults shown). The
     *  struct lives as long as the returned table needs it. */
    std::function<core::OptionTable(std::shared_ptr<void>&)> table;
};
/** Every section whose keys are declared with core::OptionTable, in README order. */
const std::vector<OptionSection>& optionSections();

/** The README block of one section: a marker line, the table, an end marker. */
std::string readmeBlock(const OptionSection& s);
/** Replaces (write) or compares (check) every section's block in the module READMEs
 *  under `root`; returns the sections whose block is missing or out of date. */
std::vector<std::string> syncReadmeTables(const std::string& root, bool write);

}  // namespace hymm::app
