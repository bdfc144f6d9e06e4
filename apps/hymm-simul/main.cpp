/**
 * @file main.cpp
 * @brief hymm-simul: simulates a scenario (.ini) into an MRPT rawlog plus ground truth.
 *        All logic lives in hymm::sim::runScenarioFile.
 */
#include <hymm/core/command_line.h>
#include <hymm/sim/run_scenario.h>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <hymm/core/error_message.h>

#include <iostream>

int main(int argc, char** argv)
{
    try
    {
        TCLAP::CmdLine cmd("hymm-simul: simulated rawlog + ground truth from a scenario .ini", ' ',
                           "0.1");
        TCLAP::SwitchArg verbose("", "verbose", "errors with MRPT's call-stack backtraces", cmd);
        TCLAP::ValueArg<std::string> config("c", "config", "scenario .ini (see configs/sim/)", true,
                                            "", "FILE.ini", cmd);
        TCLAP::ValueArg<std::string> out("o", "out", "output folder", true, "", "DIR", cmd);
        TCLAP::ValueArg<long> seed("s", "seed", "noise seed, overrides [Scenario] seed", false, 0,
                                   "N", cmd);
        TCLAP::SwitchArg png("p", "png", "also write DIR/<name>.png", cmd);
        // MRPT's TCLAP returns false after printing the help, the version or a usage error.
        if (const auto code = hymm::core::parseCommandLine(cmd, argc, argv)) return *code;

        const auto summary = hymm::sim::runScenarioFile(
            config.getValue(), out.getValue(),
            seed.isSet() ? std::optional<long>(seed.getValue()) : std::nullopt, png.getValue());
        std::cout << summary.toString();
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-simul: " << hymm::core::errorMessage(e, hymm::core::hasFlag(argc, argv, "--verbose")) << "\n";
        return 1;
    }
}
