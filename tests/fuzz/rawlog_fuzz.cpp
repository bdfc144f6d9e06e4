/**
 * @file rawlog_fuzz.cpp
 * @brief libFuzzer target: rawlog bytes -> io::RawlogReader -> DenseSlam::processEntry
 *        with every dense layer, the delayed store and the motion layers on.
 *
 * A thrown std::exception is the expected answer to a bad rawlog; a crash, a sanitizer
 * report, a hang or an allocation beyond libFuzzer's limit is a bug. The state must also
 * stay finite: a NaN that reaches the filter is reported as a crash (abort).
 */
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/io/RawlogReader.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>

#include "fuzz_util.h"

namespace
{
std::unique_ptr<mrpt::config::CConfigFileMemory> g_config;
std::string g_rawlog_path;

// The chapter-3 configuration with everything that consumes a scan switched on.
void makeConfig()
{
    std::ifstream in(std::string(HYMM_SOURCE_DIR) + "/configs/ch3_slam.ini");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.empty()) std::abort();  // the harness itself is broken
    g_config = std::make_unique<mrpt::config::CConfigFileMemory>(text);
    g_config->write("DenseSlam", "dense_layers", "points,occupancy,particles,sog,property");
    g_config->write("DelayedDenseStore", "enabled", "true");
    g_config->write("DynamicSlam", "enabled", "true");
    // Coarser maps than the chapter-3 run, so that an input costs a fraction of the time:
    // every layer's code still runs on every scan (exec/s: tests/fuzz/README.md).
    g_config->write("OccupancyLayer", "cell_size_m", "1.0");
    g_config->write("ParticlesLayer", "samples_per_return", "2");
    // The harness swallows exceptions: a config the pipeline refuses would fuzz nothing.
    try
    {
        (void)hymm::denseslam::DenseSlam::fromConfig(*g_config);
    }
    catch (const std::exception&)
    {
        std::abort();
    }
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    makeConfig();
    g_rawlog_path = (hymm::fuzz::scratchDir("rawlog_fuzz") / "input.rawlog").string();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    hymm::fuzz::writeBytes(g_rawlog_path, data, size);
    // Bounded work per input: the first entries exercise every code path a longer log does
    // (the longest seed has 40).
    constexpr size_t kMaxEntries = 40;
    try
    {
        auto slam = hymm::denseslam::DenseSlam::fromConfig(*g_config);
        hymm::io::RawlogReader reader(g_rawlog_path);
        hymm::io::RawlogEntry entry;
        while (reader.entriesRead() < kMaxEntries && reader.next(entry)) slam.processEntry(entry);
        slam.refreshRegions();
        if (!slam.ekf().mean().allFinite()) std::abort();
    }
    catch (const std::exception&)
    {
        // A clear error is the right answer to a corrupt rawlog.
    }
    return 0;
}
