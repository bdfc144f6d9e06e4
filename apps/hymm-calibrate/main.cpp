/**
 * @file main.cpp
 * @brief hymm-calibrate: calibrates a converter's noise model (control noise per
 *        odometry sample, range and bearing noise) against a run's ground truth and
 *        prints the values as the converter's .ini keys. All logic lives in
 *        hymm::datasets (NoiseCalibration.h).
 */
#include <hymm/core/command_line.h>
#include <hymm/core/output_files.h>
#include <hymm/datasets/NoiseCalibration.h>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <hymm/core/error_message.h>

#include <fstream>
#include <iostream>
#include <stdexcept>

int main(int argc, char** argv)
{
    try
    {
        TCLAP::CmdLine cmd("hymm-calibrate: converter noise model from a run's ground truth", ' ',
                           "0.1");
        TCLAP::SwitchArg verbose("", "verbose", "errors with MRPT's call-stack backtraces", cmd);
        TCLAP::ValueArg<std::string> format("f", "format", "mrclam", false, "mrclam", "FORMAT",
                                            cmd);
        TCLAP::MultiArg<std::string> input(
            "i", "input", "original files or folders holding them (repeatable)", true, "PATH",
            cmd);
        TCLAP::ValueArg<int> robot("r", "robot", "robot whose log is calibrated", true, 0, "N",
                                   cmd);
        TCLAP::ValueArg<std::string> config(
            "c", "config", "ini with [MrclamImporter] and [NoiseCalibration]", false, "",
            "FILE.ini", cmd);
        TCLAP::ValueArg<std::string> out(
            "o", "out", "also write the report and the ini keys to this file", false, "", "FILE",
            cmd);
        if (const auto code = hymm::core::parseCommandLine(cmd, argc, argv)) return *code;
        if (format.getValue() != "mrclam")
            throw std::invalid_argument("--format " + format.getValue() +
                                        ": only mrclam has a ground truth to calibrate against");

        const auto res = hymm::datasets::calibrateMrclam(input.getValue(), robot.getValue(),
                                                         config.getValue());
        std::string text = res.toString() + "\n# [MrclamImporter] keys calibrated on " +
                           res.source + "\n" + res.iniLines();
        std::cout << text;
        if (!out.getValue().empty())
        {
            hymm::core::writeFileAtomically(out.getValue(), text);
        }
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-calibrate: " << hymm::core::errorMessage(e, hymm::core::hasFlag(argc, argv, "--verbose")) << "\n";
        return 1;
    }
}
