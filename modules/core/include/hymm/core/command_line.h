/**
 * @file command_line.h
 * @brief Parsing of the apps' command lines with MRPT's TCLAP.
 *
 * MRPT's TCLAP::CmdLine::parse() returns false both after --help/--version (usage
 * printed, success) and after a usage error (already described on stderr): an app that
 * only checks the return value either carries on with empty arguments or exits 0 on an
 * error. This tells the two apart.
 */
#pragma once

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstring>
#include <optional>

namespace hymm::core
{
/** Parses argv; returns std::nullopt when the app should run, otherwise the exit code:
 *  0 after --help / --version, 1 after a usage error. */
inline std::optional<int> parseCommandLine(TCLAP::CmdLine& cmd, int argc, char** argv)
{
    if (cmd.parse(argc, argv)) return std::nullopt;
    for (int i = 1; i < argc; ++i)
        for (const char* done : {"-h", "--help", "--version"})
            if (std::strcmp(argv[i], done) == 0) return 0;
    return 1;
}

}  // namespace hymm::core
