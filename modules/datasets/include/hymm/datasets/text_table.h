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

/** The rows readNumericTable keeps, with the 1-based line number of each. */
struct NumericTable
{
    std::vector<std::vector<double>> rows;
    std::vector<size_t> lines;
};

/** readNumericTable, keeping the line number of every row (for errors naming it). */
NumericTable readNumericTableLines(const std::string& path, size_t min_cols,
                                   ImportSummary* summary = nullptr,
                                   const std::string& skip_reason = "malformed_line");

/**
 * Checks the times in column 0 of `t` (rows of `what`, e.g. "odometry"). Throws
 * std::runtime_error naming `path` and the line when a time is negative (a rawlog
 * timestamp cannot hold it), or when one row's time jumps ahead of the rows on both sides
 * (a malformed time would otherwise make every later row "non-monotonic"). A row whose
 * own time goes back, and a non-finite time, are left for the importer to skip and count.
 */
void checkTimeColumn(const NumericTable& t, const std::string& path, const std::string& what);

}  // namespace hymm::datasets
