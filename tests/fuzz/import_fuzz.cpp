/**
 * @file import_fuzz.cpp
 * @brief libFuzzer target: the dataset importers' inputs (MRCLAM text files, Victoria
 *        Park .mat + text, ACFR car park .mat) -> hymm::datasets::importDataset.
 *
 * The first byte picks the format; the rest holds that format's input files separated by
 * fuzz::fileSeparator() (make_fuzz_seeds writes valid examples of each). A
 * std::exception is the expected answer to bad input; a crash or sanitizer report is not.
 */
#include <hymm/datasets/import_dataset.h>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzz_util.h"

namespace
{
namespace fs = std::filesystem;

struct Format
{
    const char* name;
    std::vector<const char*> files;
};

// The input files of each importer, in the order they are packed.
const std::vector<Format>& formats()
{
    static const std::vector<Format> f = {
        {"mrclam",
         {"Robot1_Odometry.dat", "Robot1_Measurement.dat", "Barcodes.dat",
          "Landmark_Groundtruth.dat", "Robot1_Groundtruth.dat"}},
        {"victoria", {"aa3_dr.mat", "measurements.dat", "aa3_gpsx.mat"}},
        {"carpark", {"data_set.mat", "beac_juan3.mat"}},
    };
    return f;
}

fs::path g_dir;
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    g_dir = hymm::fuzz::scratchDir("import_fuzz");
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1) return 0;
    const Format& format = formats()[data[0] % formats().size()];
    const fs::path in = g_dir / "in";
    const fs::path out = g_dir / "out";
    fs::remove_all(in);
    fs::remove_all(out);
    fs::create_directories(in);
    const auto parts = hymm::fuzz::splitFiles(data + 1, size - 1, format.files.size());
    // Files past the parts given are absent (optional inputs, or a missing-file error).
    for (size_t i = 0; i < parts.size(); ++i)
        hymm::fuzz::writeBytes(in / format.files[i],
                               reinterpret_cast<const uint8_t*>(parts[i].data()), parts[i].size());
    try
    {
        (void)hymm::datasets::importDataset(format.name, {in.string()}, out.string());
    }
    catch (const std::exception&)
    {
    }
    return 0;
}
