/**
 * @file ini_fuzz.cpp
 * @brief libFuzzer target: .ini text -> core::openConfigFile -> every options loader the
 *        apps use (hymm-slam, hymm-simul, hymm-eval, hymm-import, hymm-calibrate).
 *
 * A std::exception is the expected answer to a bad config. Besides crashes and sanitizer
 * reports, the target checks one property: a scenario that loads saves to text that
 * loads again (the round trip hymm-simul relies on to record its effective config).
 */
#include <hymm/core/config_utils.h>
#include <hymm/datasets/CarParkImporter.h>
#include <hymm/datasets/MrclamImporter.h>
#include <hymm/datasets/NoiseCalibration.h>
#include <hymm/datasets/VictoriaParkImporter.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/eval/LandmarkEvaluator.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <hymm/sim/Scenario.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>

#include "fuzz_util.h"

namespace
{
std::string g_ini_path;

template <typename F>
void expectCleanError(F&& load)
{
    try
    {
        load();
    }
    catch (const std::exception&)
    {
    }
}

template <typename Opts>
void loadSection(const mrpt::config::CConfigFileBase& cfg, const char* section)
{
    expectCleanError([&] { Opts().loadFromConfigFile(cfg, section); });
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    g_ini_path = (hymm::fuzz::scratchDir("ini_fuzz") / "input.ini").string();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    hymm::fuzz::writeBytes(g_ini_path, data, size);
    std::unique_ptr<mrpt::config::CConfigFileBase> cfg;
    try
    {
        cfg = hymm::core::openConfigFile(g_ini_path);
    }
    catch (const std::exception&)
    {
        return 0;
    }
    expectCleanError([&] { (void)hymm::denseslam::DenseSlam::fromConfig(*cfg); });
    expectCleanError(
        [&]
        {
            hymm::sim::Scenario s;
            s.loadFromConfigFile(*cfg);
            // What loaded must reload from its own saved text.
            hymm::sim::Scenario again;
            try
            {
                again.loadFromConfigFile(mrpt::config::CConfigFileMemory(s.toIniText()));
            }
            catch (const std::exception&)
            {
                std::abort();
            }
        });
    loadSection<hymm::eval::LandmarkEvaluator::Options>(*cfg, "LandmarkEvaluator");
    loadSection<hymm::eval::TrajectoryEvaluator::Options>(*cfg, "TrajectoryEvaluator");
    loadSection<hymm::datasets::VictoriaParkImporter::Options>(*cfg, "VictoriaParkImporter");
    loadSection<hymm::datasets::CarParkImporter::Options>(*cfg, "CarParkImporter");
    loadSection<hymm::datasets::MrclamImporter::Options>(*cfg, "MrclamImporter");
    loadSection<hymm::datasets::NoiseCalibrationOptions>(*cfg, "NoiseCalibration");
    return 0;
}
