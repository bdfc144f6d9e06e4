/**
 * @file main.cpp
 * @brief hymm-import: converts a public dataset (original files) to an MRPT rawlog plus
 *        ground-truth files. All logic lives in hymm::datasets::importDataset.
 */
#include <hymm/datasets/import_dataset.h>
#include <hymm/core/command_line.h>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <hymm/core/error_message.h>

#include <iostream>

int main(int argc, char** argv)
{
    try
    {
        TCLAP::CmdLine cmd("hymm-import: dataset to MRPT rawlog + ground truth", ' ', "0.1");
        TCLAP::SwitchArg verbose("", "verbose", "errors with MRPT's call-stack backtraces", cmd);
        TCLAP::ValueArg<std::string> format(
            "f", "format", "victoria | carpark | mrclam", true, "", "FORMAT", cmd);
        TCLAP::MultiArg<std::string> input(
            "i", "input", "original files or folders holding them (repeatable)", true, "PATH",
            cmd);
        TCLAP::ValueArg<std::string> out("o", "out", "output folder", true, "", "DIR", cmd);
        TCLAP::ValueArg<std::string> config(
            "c", "config", "ini with the importer's section", false, "", "FILE.ini", cmd);
        if (const auto code = hymm::core::parseCommandLine(cmd, argc, argv)) return *code;

        const auto summary = hymm::datasets::importDataset(
            format.getValue(), input.getValue(), out.getValue(), config.getValue());
        std::cout << summary.toString();
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-import: " << hymm::core::errorMessage(e, hymm::core::hasFlag(argc, argv, "--verbose")) << "\n";
        return 1;
    }
}
