#include "test_files.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace hymm::datasets::testing
{
TempDir::TempDir()
{
    std::string tmpl = (std::filesystem::temp_directory_path() / "hymm_ds_XXXXXX").string();
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    if (!mkdtemp(buf.data())) throw std::runtime_error("mkdtemp failed for " + tmpl);
    path_ = buf.data();
}

TempDir::~TempDir()
{
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

void writeText(const std::string& path, const std::string& content)
{
    std::ofstream f(path);
    f << content;
    if (!f) throw std::runtime_error("cannot write " + path);
}

mrpt::obs::CRawlog loadRawlog(const std::string& path)
{
    mrpt::obs::CRawlog log;
    if (!log.loadFromRawLogFile(path)) throw std::runtime_error("cannot load rawlog " + path);
    return log;
}

}  // namespace hymm::datasets::testing
