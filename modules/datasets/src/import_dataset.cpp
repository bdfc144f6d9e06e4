#include "hymm/datasets/import_dataset.h"

#include <hymm/core/config_utils.h>
#include <hymm/core/output_files.h>

#include <filesystem>
#include <stdexcept>

#include "hymm/datasets/CarParkImporter.h"
#include "hymm/datasets/MrclamImporter.h"
#include "hymm/datasets/VictoriaParkImporter.h"

namespace hymm::datasets
{
namespace fs = std::filesystem;

namespace
{
template <typename Opts>
Opts loadOptions(const std::string& config_file, const std::string& section)
{
    Opts o;
    if (!config_file.empty()) o.loadFromConfigFile(*hymm::core::openConfigFile(config_file), section);
    return o;
}
}  // namespace

std::string findInputFile(const std::vector<std::string>& paths, const std::string& file_name,
                          bool required)
{
    std::string searched;
    for (const auto& p : paths)
    {
        std::error_code ec;
        if (fs::is_directory(p, ec))
        {
            const fs::path candidate = fs::path(p) / file_name;
            if (fs::is_regular_file(candidate, ec)) return candidate.string();
        }
        else if (fs::path(p).filename() == file_name)
        {
            if (!fs::is_regular_file(p, ec))
                throw std::runtime_error("input '" + p + "' does not exist or is not a file");
            return p;
        }
        searched += (searched.empty() ? "" : ", ") + p +
                    (fs::exists(p, ec) ? std::string() : std::string(" (does not exist)"));
    }
    if (required)
        throw std::runtime_error("required input '" + file_name + "' not found in: " +
                                 (searched.empty() ? std::string("(no input given)") : searched));
    return "";
}

void ensureOutputDir(const std::string& dir)
{
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir))
        throw std::runtime_error("cannot create output folder '" + dir + "'" +
                                 (ec ? ": " + ec.message() : std::string()));
}

namespace
{
ImportSummary runImporter(const std::string& format, const std::vector<std::string>& inputs,
                          const std::string& out_dir, const std::string& config_file)
{
    if (format == "victoria")
    {
        const auto o = loadOptions<VictoriaParkImporter::Options>(config_file, "VictoriaParkImporter");
        return VictoriaParkImporter(o).run(VictoriaParkImporter::findInputs(inputs), out_dir);
    }
    if (format == "carpark")
    {
        const auto o = loadOptions<CarParkImporter::Options>(config_file, "CarParkImporter");
        return CarParkImporter(o).run(CarParkImporter::findInputs(inputs), out_dir);
    }
    if (format == "mrclam")
    {
        const auto o = loadOptions<MrclamImporter::Options>(config_file, "MrclamImporter");
        return MrclamImporter(o).run(MrclamImporter::findInputs(inputs, o.robot), out_dir);
    }
    throw std::invalid_argument("unknown format '" + format +
                                "' (expected victoria, carpark or mrclam)");
}
}  // namespace

ImportSummary importDataset(const std::string& format, const std::vector<std::string>& inputs,
                            const std::string& out_dir, const std::string& config_file)
{
    if (format != "victoria" && format != "carpark" && format != "mrclam")
        throw std::invalid_argument("unknown format '" + format +
                                    "' (expected victoria, carpark or mrclam)");
    // The folder is checked before any work and the files appear only when all were
    // written (core::OutputFolder): an importer failing on a later input leaves nothing.
    ensureOutputDir(out_dir);
    core::OutputFolder out(out_dir);
    out.prepare();
    std::string staging = out.staging();
    staging.pop_back();  // no trailing '/': the importers append "/<name>"
    auto summary = runImporter(format, inputs, staging, config_file);
    out.commit();
    for (auto& f : summary.outputs)
        if (f.rfind(staging, 0) == 0) f = (fs::path(out_dir) / fs::path(f.substr(staging.size() + 1))).string();
    return summary;
}

}  // namespace hymm::datasets
