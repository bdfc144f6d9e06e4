/**
 * @file text_table.h
 * @brief Tolerant reader of whitespace/comma separated numeric text tables (the UTIAS
 *        MRCLAM .dat files, the ACFR ASCII releases).
 */
#pragma once

#include <string>
#include <vector>

namespace hymm::datasets
{
struct ImportSummary;

/**
 * Reads the rows of `path` that hold at least `min_cols` numbers. Blank lines and lines
 * starting with '#' or '%' are comments. A row with too few columns or a token that is
 * not a number is skipped and counted in `summary` under `skip_reason` (when given).
 * Non-finite numbers ("nan", "inf") are returned as is, for the caller to count.
 * Throws std::runtime_error naming the path if the file cannot be opened.
 */
std::vector<std::vector<double>> readNumericTable(
    const std::string& path, size_t min_cols, ImportSummary* summary = nullptr,
    const std::string& skip_reason = "malformed_line");

}  // namespace hymm::datasets
