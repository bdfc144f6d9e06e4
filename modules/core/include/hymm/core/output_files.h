/**
 * @file output_files.h
 * @brief Writing result files so that a failure is never silent and never leaves a
 *        complete-looking file: every file is written under a temporary name next to its
 *        final one, each write and the close are checked, and only then is it renamed.
 *        Any failure throws std::runtime_error naming the file (and the system error).
 *
 * OutputFolder gives a whole run the same property for a folder of results: it is
 * checked and made before any work, the results of an earlier run in it are removed,
 * and the run's files appear only when all of them were written.
 */
#pragma once

#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace hymm::core
{
/** Writes `bytes` to `<path>.tmp-<pid>`, checking every write and the close, then renames
 *  it to `path`. On failure the temporary file is removed and the error names `path`.
 *  A `path` that exists and is not a regular file (/dev/stdout, a FIFO) is written in
 *  place, with the same checks. */
void writeFileAtomically(const std::string& path, std::string_view bytes);

/** The same, gzip-compressed at `level` (1 fast .. 9 small), as MRPT's CFileGZOutputStream
 *  writes (zlib's gzip header, so MRPT and gunzip read it). */
void writeGzFileAtomically(const std::string& path, std::string_view bytes, int level = 1);

/** A text file built in memory: stream into it, then commit() writes it atomically. Not
 *  committing (an exception on the way) writes nothing. */
class AtomicTextFile : public std::ostringstream
{
public:
    explicit AtomicTextFile(std::string path) : path_(std::move(path)) {}
    const std::string& path() const { return path_; }
    /** Throws if formatting failed or the file cannot be written. */
    void commit();

private:
    std::string path_;
};

/**
 * The output folder of a run (hymm-slam's --out).
 *
 * prepare() checks the folder before any work: creates it if missing (its parent must
 * exist), refuses a path that is not a writable folder, and removes the results of an
 * earlier run in it: the files named in its manifest `.hymm-outputs` (written by the
 * run that produced them) and any leftover staging folder of a run that failed. Other
 * files in the folder are left alone.
 *
 * The run then writes its files into staging() (`<dir>/.hymm-partial-<pid>/`, on the
 * same file system); commit() moves each into the folder by rename and writes the new
 * manifest. Without commit() (a failed run) the destructor removes the staging folder,
 * so a failed run leaves no results, complete-looking or not.
 */
class OutputFolder
{
public:
    static constexpr const char* kManifest = ".hymm-outputs";

    explicit OutputFolder(std::string dir) : dir_(std::move(dir)) {}
    ~OutputFolder();
    OutputFolder(const OutputFolder&) = delete;
    OutputFolder& operator=(const OutputFolder&) = delete;

    /** Checks / makes the folder, removes earlier results, makes the staging folder.
     *  Throws naming the folder when it cannot be used. */
    void prepare();

    /** Where the run writes, '/'-terminated. */
    std::string staging() const;

    /** Moves every staged file into the folder and writes the manifest; returns the
     *  file names. Throws naming the file on failure (files moved so far stay). */
    std::vector<std::string> commit();

    const std::string& dir() const { return dir_; }

private:
    std::string dir_;
    std::string staging_;
    bool committed_ = false;
};

}  // namespace hymm::core
