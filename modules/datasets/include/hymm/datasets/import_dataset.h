/**
 * @file import_dataset.h
 * @brief One entry point for all dataset converters (what the hymm-import app calls),
 *        and the input/output path helpers they share.
 */
#pragma once

#include <string>
#include <vector>

#include "hymm/datasets/ImportSummary.h"

namespace hymm::datasets
{
/**
 * Converts a dataset. `format` is "victoria", "carpark" or "mrclam"; `inputs` are files
 * and/or folders holding the original files (see each importer); `out_dir` is created
 * if needed; `config_file` (optional, may be empty) is an .ini with the importer's
 * section ([VictoriaParkImporter], [CarParkImporter], [MrclamImporter]).
 * Throws std::exception with a message naming the offending path/key on bad input.
 * The outputs are written through core::OutputFolder: files of an earlier import into
 * `out_dir` (its `.hymm-outputs` manifest) are removed first, and the new files appear
 * only when the whole import succeeded, so a failure leaves no complete-looking rawlog.
 */
ImportSummary importDataset(const std::string& format, const std::vector<std::string>& inputs,
                            const std::string& out_dir, const std::string& config_file = "");

/**
 * Returns the path of the input called `file_name`: an entry of `paths` with that file
 * name, or `<dir>/<file_name>` for an entry that is a folder. Returns "" if not found
 * and not `required`; throws std::runtime_error listing the places searched otherwise.
 */
std::string findInputFile(const std::vector<std::string>& paths, const std::string& file_name,
                          bool required);

/** Creates `dir` (and parents) if missing; throws if it cannot or is not a folder. */
void ensureOutputDir(const std::string& dir);

}  // namespace hymm::datasets
