#include "hymm/datasets/text_table.h"

#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "hymm/datasets/ImportSummary.h"

namespace hymm::datasets
{
namespace
{
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

std::vector<std::vector<double>> readNumericTable(
    const std::string& path, size_t min_cols, ImportSummary* summary,
    const std::string& skip_reason)
{
    std::ifstream f(path);
    if (!f) throw std::runtime_error("cannot open '" + path + "'");
    std::vector<std::vector<double>> rows;
    std::vector<double> vals;
    std::string line;
    while (std::getline(f, line))
    {
        const auto p = line.find_first_not_of(" \t\r");
        if (p == std::string::npos || line[p] == '#' || line[p] == '%') continue;
        if (!parseLine(line, vals) || vals.size() < min_cols)
        {
            if (summary) summary->skip(skip_reason);
            continue;
        }
        rows.push_back(vals);
    }
    if (f.bad()) throw std::runtime_error("error reading '" + path + "'");
    return rows;
}

}  // namespace hymm::datasets
