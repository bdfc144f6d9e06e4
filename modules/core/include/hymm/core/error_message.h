/**
 * @file error_message.h
 * @brief What the apps print for an error: the messages of the exception and of the
 *        exceptions nested in it, without MRPT's call-stack backtraces (tens of lines per
 *        error, of use to a developer only) unless asked for with --verbose.
 */
#pragma once

#include <mrpt/core/exceptions.h>

#include <cstring>
#include <sstream>
#include <string>

namespace hymm::core
{
/** MRPT's exception_to_str() text without its banners, "Location:" lines and call
 *  stacks ("Message: " prefixes dropped); the whole text when `verbose`. */
inline std::string errorMessage(const std::exception& e, bool verbose)
{
    const std::string full = mrpt::exception_to_str(e);
    if (verbose) return full;
    std::istringstream in(full);
    std::string line, out;
    bool in_stack = false;
    while (std::getline(in, line))
    {
        if (line.rfind("Call stack backtrace:", 0) == 0)
        {
            in_stack = true;
            continue;
        }
        if (line.rfind("====", 0) == 0)
        {
            in_stack = false;
            continue;
        }
        if (in_stack || line.rfind("Location: ", 0) == 0) continue;
        if (line.rfind("Message: ", 0) == 0) line.erase(0, std::strlen("Message: "));
        // A message that embeds an MRPT exception text carries its stack inline.
        if (const auto cut = line.find("Call stack backtrace:"); cut != std::string::npos)
        {
            line.erase(cut);
            in_stack = true;
        }
        if (const auto cut = line.find("==== MRPT exception ===="); cut != std::string::npos)
            line.erase(cut, std::strlen("==== MRPT exception ===="));
        if (line.find_first_not_of(" \t") == std::string::npos) continue;
        // "...: " followed by the embedded message on the next line: one line.
        if (!out.empty() && out.back() != ' ') out += '\n';
        out += line;
    }
    return out.empty() ? std::string(e.what()) : out;
}

/** Whether `flag` (e.g. "--verbose") is on the command line; usable when parsing failed. */
inline bool hasFlag(int argc, char** argv, const char* flag)
{
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], flag) == 0) return true;
    return false;
}

}  // namespace hymm::core
