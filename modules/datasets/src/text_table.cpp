#include "hymm/datasets/text_table.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "hymm/datasets/ImportSummary.h"

namespace hymm::datasets
{
namespace
{
std::string number(double v)
{
    std::ostringstream o;
    o << std::setprecision(15) << v;
    return o.str();
}

bool isSeparator(char c) { return c == ' ' || c == '\t' || c == ',' || c == '\r'; }

/** Parses all tokens of `line`; false if one is not a number. */
bool parseLine(const std::string& line, std::vector<double>& out)
{
    out.clear();
    size_t i = 0;
    while (i < line.size())
    {
        while (i < line.size() && isSeparator(line[i])) ++i;
        if (i >= line.size()) break;
        size_t j = i;
        while (j < line.size() && !isSeparator(line[j])) ++j;
        const std::string tok = line.substr(i, j - i);
        char* end = nullptr;
        const double v = std::strtod(tok.c_str(), &end);
        if (end == tok.c_str() || *end != '\0') return false;
        out.push_back(v);
        i = j;
    }
    return true;
}
}  // namespace

NumericTable readNumericTableLines(const std::string& path, size_t min_cols,
                                   ImportSummary* summary, const std::string& skip_reason)
{
    std::ifstream f(path);
    if (!f) throw std::runtime_error("cannot open '" + path + "'");
    NumericTable t;
    std::vector<double> vals;
    std::string line;
    size_t number = 0;
    while (std::getline(f, line))
    {
        ++number;
        const auto p = line.find_first_not_of(" \t\r");
        if (p == std::string::npos || line[p] == '#' || line[p] == '%') continue;
        if (!parseLine(line, vals) || vals.size() < min_cols)
        {
            if (summary) summary->skip(skip_reason);
            continue;
        }
        t.rows.push_back(vals);
        t.lines.push_back(number);
    }
    if (f.bad()) throw std::runtime_error("error reading '" + path + "'");
    return t;
}

std::vector<std::vector<double>> readNumericTable(
    const std::string& path, size_t min_cols, ImportSummary* summary,
    const std::string& skip_reason)
{
    return readNumericTableLines(path, min_cols, summary, skip_reason).rows;
}

void checkTimeColumn(const NumericTable& t, const std::string& path, const std::string& what)
{
    const auto at = [&](size_t i) {
        return "'" + path + "' line " + std::to_string(t.lines[i]) + ": ";
    };
    // Indices of the last two rows whose times did not decrease.
    long prev = -1, before = -1;
    for (size_t i = 0; i < t.rows.size(); ++i)
    {
        const double time = t.rows[i][0];
        if (!std::isfinite(time)) continue;  // the importer skips and counts it
        if (time < 0)
            throw std::runtime_error(at(i) + what + " time " + number(time) +
                                     " is negative (rawlog times count from 1970)");
        if (prev < 0 || time >= t.rows[static_cast<size_t>(prev)][0])
        {
            before = prev;
            prev = static_cast<long>(i);
            continue;
        }
        // Time goes back. If this row still follows the row before the previous one, the
        // previous row jumped ahead of both neighbours: skipping everything after it as
        // "non-monotonic" would drop the rest of the file for one bad line.
        const auto p = static_cast<size_t>(prev);
        if (before < 0 || time >= t.rows[static_cast<size_t>(before)][0])
            throw std::runtime_error(
                at(p) + what + " time " + number(t.rows[p][0]) +
                " is later than the next line's (" + std::to_string(t.lines[i]) + ": " +
                number(time) + ")" +
                (before < 0 ? std::string()
                            : " though that follows line " +
                                  std::to_string(t.lines[static_cast<size_t>(before)]) +
                                  " (" + number(t.rows[static_cast<size_t>(before)][0]) + ")") +
                "; times must not decrease");
        // Otherwise this row alone goes back: the importer skips and counts it.
    }
}

}  // namespace hymm::datasets
