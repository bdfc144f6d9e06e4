#include "hymm/core/output_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace hymm::core
{
namespace fs = std::filesystem;

namespace
{
// A target that exists and is not a regular file (/dev/stdout, a FIFO, /dev/full) is
// written in place: renaming a file over it would replace the device.
bool writeInPlace(const std::string& path)
{
    struct stat st{};
    return ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode);
}

std::string tempNameFor(const std::string& path)
{
    return writeInPlace(path) ? path : path + ".tmp-" + std::to_string(::getpid());
}

void removeTemp(const std::string& tmp, const std::string& path)
{
    if (tmp != path) ::unlink(tmp.c_str());
}

std::runtime_error writeError(const std::string& path, int err)
{
    return std::runtime_error("cannot write '" + path + "': " + std::strerror(err));
}

void renameInto(const std::string& tmp, const std::string& path)
{
    if (tmp == path) return;
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
    {
        const int err = errno;
        ::unlink(tmp.c_str());
        throw std::runtime_error("cannot rename '" + tmp + "' to '" + path +
                                 "': " + std::strerror(err));
    }
}
}  // namespace

void writeFileAtomically(const std::string& path, std::string_view bytes)
{
    const std::string tmp = tempNameFor(path);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);  // NOLINT
    if (fd < 0) throw writeError(path, errno);
    size_t done = 0;
    while (done < bytes.size())
    {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0)
        {
            const int err = n < 0 ? errno : EIO;
            ::close(fd);
            removeTemp(tmp, path);
            throw writeError(path, err);
        }
        done += static_cast<size_t>(n);
    }
    if (::close(fd) != 0)
    {
        const int err = errno;
        removeTemp(tmp, path);
        throw writeError(path, err);
    }
    renameInto(tmp, path);
}

void writeGzFileAtomically(const std::string& path, std::string_view bytes, int level)
{
    const std::string tmp = tempNameFor(path);
    const std::string mode = "wb" + std::to_string(level);
    errno = 0;
    gzFile f = gzopen(tmp.c_str(), mode.c_str());
    if (!f) throw writeError(path, errno ? errno : ENOMEM);
    // zlib takes unsigned lengths: write in pieces.
    size_t done = 0;
    while (done < bytes.size())
    {
        const auto piece = static_cast<unsigned>(std::min<size_t>(bytes.size() - done, 1u << 30));
        const int n = gzwrite(f, bytes.data() + done, piece);
        if (n <= 0)
        {
            int code = Z_OK;
            const std::string msg = gzerror(f, &code);
            const int err = errno;
            gzclose(f);
            removeTemp(tmp, path);
            throw std::runtime_error("cannot write '" + path + "': " +
                                     (code == Z_ERRNO ? std::strerror(err) : msg));
        }
        done += static_cast<size_t>(n);
    }
    errno = 0;
    const int rc = gzclose(f);  // flushes the compressor: a full disk shows here
    if (rc != Z_OK)
    {
        const int err = errno;
        removeTemp(tmp, path);
        throw std::runtime_error("cannot write '" + path + "': " +
                                 (rc == Z_ERRNO && err ? std::strerror(err)
                                                       : "zlib error " + std::to_string(rc)));
    }
    renameInto(tmp, path);
}

void AtomicTextFile::commit()
{
    if (fail()) throw std::runtime_error("cannot format '" + path_ + "'");
    writeFileAtomically(path_, str());
}

OutputFolder::~OutputFolder()
{
    if (!staging_.empty() && !committed_)
    {
        std::error_code ec;
        fs::remove_all(staging_, ec);  // a failed run leaves nothing behind
    }
}

void OutputFolder::prepare()
{
    if (dir_.empty()) throw std::invalid_argument("no output folder given");
    std::error_code ec;
    const fs::path dir(dir_);
    if (!fs::exists(dir, ec))
    {
        if (!fs::create_directory(dir, ec))
            throw std::runtime_error("cannot create output folder '" + dir_ + "': " +
                                     (ec ? ec.message() : "unknown error"));
    }
    else if (!fs::is_directory(dir, ec))
        throw std::runtime_error("output folder '" + dir_ + "' exists and is not a folder");
    if (::access(dir_.c_str(), W_OK | X_OK) != 0)
        throw std::runtime_error("output folder '" + dir_ + "' is not writable: " +
                                 std::strerror(errno));

    // Results of an earlier run: the files its manifest names, and staging folders of
    // runs that died. Names with a path separator are not ours and are left alone.
    const fs::path manifest = dir / kManifest;
    if (fs::exists(manifest, ec))
    {
        std::ifstream in(manifest);
        std::string name;
        while (std::getline(in, name))
        {
            if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
                continue;
            fs::remove(dir / name, ec);
            if (ec)
                throw std::runtime_error("cannot remove '" + (dir / name).string() +
                                         "' (a result of an earlier run): " + ec.message());
        }
        fs::remove(manifest, ec);
    }
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().filename().string().rfind(".hymm-partial-", 0) == 0) fs::remove_all(e.path(), ec);

    staging_ = (dir / (".hymm-partial-" + std::to_string(::getpid()))).string();
    fs::remove_all(staging_, ec);
    if (!fs::create_directory(staging_, ec))
        throw std::runtime_error("cannot write in output folder '" + dir_ + "': " +
                                 (ec ? ec.message() : "unknown error"));
}

std::string OutputFolder::staging() const
{
    if (staging_.empty()) throw std::logic_error("OutputFolder::staging() before prepare()");
    return staging_ + "/";
}

std::vector<std::string> OutputFolder::commit()
{
    if (staging_.empty()) throw std::logic_error("OutputFolder::commit() before prepare()");
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(staging_, ec))
        if (e.is_regular_file()) names.push_back(e.path().filename().string());
    if (ec) throw std::runtime_error("cannot list '" + staging_ + "': " + ec.message());
    std::sort(names.begin(), names.end());
    // The manifest first: if a rename fails, the next run still removes what was moved.
    std::string manifest;
    for (const auto& n : names) manifest += n + "\n";
    writeFileAtomically((fs::path(dir_) / kManifest).string(), manifest);
    for (const auto& n : names) renameInto(staging_ + "/" + n, (fs::path(dir_) / n).string());
    committed_ = true;
    fs::remove_all(staging_, ec);
    return names;
}

}  // namespace hymm::core
