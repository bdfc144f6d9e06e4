/**
 * @file fuzz_util.h
 * @brief Shared by the libFuzzer targets: per-process scratch paths and the splitting
 *        of one fuzz input into several files.
 */
#pragma once

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace hymm::fuzz
{
/** A scratch folder of this process (the fuzzer may run several jobs at once). */
inline std::filesystem::path scratchDir(const std::string& name)
{
    const auto dir = std::filesystem::temp_directory_path() /
                     ("hymm_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return dir;
}

inline void writeBytes(const std::filesystem::path& p, const uint8_t* data, size_t size)
{
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

/** The separator between the files packed into one input (see make_fuzz_seeds). */
inline const std::string& fileSeparator()
{
    static const std::string s = "@@HYMM@@";
    return s;
}

/** Splits `data` at fileSeparator() into at most `n` parts (the last takes the rest). */
inline std::vector<std::string> splitFiles(const uint8_t* data, size_t size, size_t n)
{
    const std::string all(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> parts;
    size_t from = 0;
    while (parts.size() + 1 < n)
    {
        const size_t at = all.find(fileSeparator(), from);
        if (at == std::string::npos) break;
        parts.push_back(all.substr(from, at - from));
        from = at + fileSeparator().size();
    }
    parts.push_back(all.substr(from));
    return parts;
}

}  // namespace hymm::fuzz
