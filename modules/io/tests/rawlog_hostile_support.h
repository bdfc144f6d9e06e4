// Shared by the hostile-rawlog tests: mutated rawlogs are read in a child process whose
// address space may grow only by twice the file's uncompressed size plus a fixed margin.
#pragma once

#include <gtest/gtest.h>
#include <hymm/io/RawlogReader.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>
#include <mrpt/system/filesystem.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace hymm_hostile
{
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

inline const std::string kSample = std::string(HYMM_SOURCE_DIR) + "/rawlogs/ch3_objects.rawlog";

inline std::vector<uint8_t> gunzip(const std::string& path)
{
    gzFile f = gzopen(path.c_str(), "rb");
    if (!f) throw std::runtime_error("cannot open " + path);
    std::vector<uint8_t> out;
    std::vector<uint8_t> buf(1 << 16);
    int n = 0;
    while ((n = gzread(f, buf.data(), static_cast<unsigned>(buf.size()))) > 0)
        out.insert(out.end(), buf.begin(), buf.begin() + n);
    gzclose(f);
    return out;
}

inline std::string writeGz(const std::vector<uint8_t>& data)
{
    const std::string path = mrpt::system::getTempFileName() + ".rawlog";
    gzFile f = gzopen(path.c_str(), "wb1");
    gzwrite(f, data.data(), static_cast<unsigned>(data.size()));
    gzclose(f);
    return path;
}

// Offset just past the n-th (0-based) serialised class name `name` (as MRPT 2 writes it,
// with its namespace).
inline size_t afterClassName(const std::vector<uint8_t>& d, const std::string& short_name, size_t nth)
{
    const std::string name = (short_name == "CPose3D" ? "mrpt::poses::" : "mrpt::obs::") + short_name;
    std::vector<uint8_t> pat{static_cast<uint8_t>(0x80 | name.size())};
    pat.insert(pat.end(), name.begin(), name.end());
    auto it = d.begin();
    for (size_t i = 0;; ++i)
    {
        it = std::search(it, d.end(), pat.begin(), pat.end());
        if (it == d.end()) throw std::runtime_error(name + " not found");
        if (i == nth) return static_cast<size_t>(it - d.begin()) + pat.size();
        ++it;
    }
}

inline void putU32(std::vector<uint8_t>& d, size_t at, uint32_t v) { std::memcpy(&d[at], &v, 4); }
inline uint32_t getU32(const std::vector<uint8_t>& d, size_t at)
{
    uint32_t v = 0;
    std::memcpy(&v, &d[at], 4);
    return v;
}

inline size_t virtualMemoryBytes()
{
    std::ifstream f("/proc/self/statm");
    size_t pages = 0;
    f >> pages;
    return pages * static_cast<size_t>(sysconf(_SC_PAGESIZE));
}

struct ChildResult
{
    bool exited = false;
    int code = -1;
    int signal = 0;
    std::string message;
    long max_rss_kib = 0;
};

// Reads `path` to the end in a child process whose address space may grow by at most
// `budget` bytes (no limit under ASan, whose shadow memory defeats RLIMIT_AS). Exit 0:
// a runtime_error was thrown (its text comes back through a pipe); 1: no error.
inline ChildResult readInChild(const std::string& path, size_t budget)
{
    int fds[2];
    if (pipe(fds) != 0) throw std::runtime_error("pipe");
    const pid_t pid = fork();
    if (pid == 0)
    {
        close(fds[0]);
        if (!kSanitized)
        {
            rlimit lim{};
            lim.rlim_cur = lim.rlim_max = virtualMemoryBytes() + budget;
            setrlimit(RLIMIT_AS, &lim);
        }
        int code = 1;
        std::string msg;
        try
        {
            hymm::io::RawlogReader r(path);
            hymm::io::RawlogEntry e;
            while (r.next(e))
            {
            }
        }
        catch (const std::runtime_error& e)
        {
            msg = e.what();
            code = 0;
        }
        catch (const std::exception& e)
        {
            msg = std::string("other exception: ") + e.what();
            code = 2;
        }
        if (write(fds[1], msg.data(), msg.size()) < 0) code = 3;
        close(fds[1]);
        _exit(code);
    }
    close(fds[1]);
    ChildResult res;
    char buf[4096];
    ssize_t n = 0;
    while ((n = read(fds[0], buf, sizeof(buf))) > 0) res.message.append(buf, static_cast<size_t>(n));
    close(fds[0]);
    int status = 0;
    rusage ru{};
    wait4(pid, &status, 0, &ru);
    res.exited = WIFEXITED(status);
    res.code = res.exited ? WEXITSTATUS(status) : -1;
    res.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
    res.max_rss_kib = ru.ru_maxrss;
    return res;
}

// Budget: twice the uncompressed size plus a fixed margin for MRPT and zlib.
inline size_t budgetFor(const std::vector<uint8_t>& data) { return 2 * data.size() + (64u << 20); }

inline void expectCleanError(const std::string& path, const std::vector<uint8_t>& data,
                      const std::string& entry, const std::string& what)
{
    const auto r = readInChild(path, budgetFor(data));
    ASSERT_TRUE(r.exited) << "killed by signal " << r.signal;
    ASSERT_EQ(r.code, 0) << r.message;
    EXPECT_NE(r.message.find(path), std::string::npos) << r.message;
    EXPECT_NE(r.message.find(entry), std::string::npos) << r.message;
    EXPECT_NE(r.message.find(what), std::string::npos) << r.message;
    // The peak of the child, which shares the parent's pages until it writes them.
    EXPECT_LT(static_cast<size_t>(r.max_rss_kib) * 1024,
              virtualMemoryBytes() + budgetFor(data)) << r.message;
}

inline std::vector<uint8_t> serialised(const mrpt::serialization::CSerializable& o)
{
    mrpt::io::CMemoryStream mem;
    auto arch = mrpt::serialization::archiveFrom(mem);
    arch << o;
    const auto* p = static_cast<const uint8_t*>(mem.getRawBufferData());
    return std::vector<uint8_t>(p, p + mem.getTotalBytesCount());
}

}  // namespace hymm_hostile
