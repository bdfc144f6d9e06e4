/**
 * @file test_files.h
 * @brief Scratch folders and small files for the datasets tests (nothing is read from
 *        outside the folder the test creates).
 */
#pragma once

#include <mrpt/obs/CRawlog.h>

#include <string>

namespace hymm::datasets::testing
{
/** A fresh folder under the system temp dir, removed with its contents on destruction. */
class TempDir
{
   public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::string& path() const { return path_; }
    std::string file(const std::string& name) const { return path_ + "/" + name; }

   private:
    std::string path_;
};

/** Writes `content` to `path` (throws on failure). */
void writeText(const std::string& path, const std::string& content);

/** Loads a rawlog, failing the calling test (via exception) if it cannot. */
mrpt::obs::CRawlog loadRawlog(const std::string& path);

}  // namespace hymm::datasets::testing
