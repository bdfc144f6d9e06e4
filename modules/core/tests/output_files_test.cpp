#include <gtest/gtest.h>
#include <hymm/core/output_files.h>

#include <unistd.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace
{
namespace fs = std::filesystem;
using hymm::core::AtomicTextFile;
using hymm::core::OutputFolder;

fs::path freshDir(const std::string& name)
{
    const fs::path d = fs::temp_directory_path() /
                       ("hymm_output_files_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string slurp(const fs::path& p)
{
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// The temporary name the writer uses, pointed at /dev/full: every write fails with ENOSPC.
fs::path fullDiskTarget(const fs::path& dir, const std::string& name)
{
    const fs::path target = dir / name;
    fs::create_symlink("/dev/full", target.string() + ".tmp-" + std::to_string(::getpid()));
    return target;
}

template <class F>
std::string errorOf(F&& f)
{
    try
    {
        f();
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return {};
}

TEST(OutputFilesTest, WritesAndReplacesAtomically)
{
    const auto d = freshDir("write");
    const auto p = (d / "a.txt").string();
    hymm::core::writeFileAtomically(p, "first\n");
    hymm::core::writeFileAtomically(p, "second\n");
    EXPECT_EQ(slurp(p), "second\n");
    EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator{}), 1);
}

TEST(OutputFilesTest, FullDiskIsAnErrorNamingTheFileAndLeavesNoFile)
{
    const auto d = freshDir("full");
    const auto target = fullDiskTarget(d, "summary.txt");
    const std::string err =
        errorOf([&] { hymm::core::writeFileAtomically(target.string(), std::string(1 << 16, 'x')); });
    EXPECT_NE(err.find(target.string()), std::string::npos) << err;
    EXPECT_NE(err.find("No space left"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(target));
    EXPECT_TRUE(fs::is_empty(d)) << "temporary file left behind";
}

TEST(OutputFilesTest, FullDiskGzipIsAnErrorAtClose)
{
    const auto d = freshDir("fullgz");
    const auto target = fullDiskTarget(d, "grid.gridmap");
    // Small enough to sit in zlib's buffer until gzclose flushes it.
    const std::string err =
        errorOf([&] { hymm::core::writeGzFileAtomically(target.string(), "tiny"); });
    EXPECT_NE(err.find(target.string()), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(target));
}

TEST(OutputFilesTest, DeviceTargetIsWrittenInPlace)
{
    // /dev/full is not replaced by a file: the write fails, naming it.
    const std::string err = errorOf([] { hymm::core::writeFileAtomically("/dev/full", "x"); });
    EXPECT_NE(err.find("'/dev/full'"), std::string::npos) << err;
    EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

TEST(OutputFilesTest, GzipRoundTrip)
{
    const auto d = freshDir("gz");
    const auto p = (d / "x.gz").string();
    const std::string payload(100000, 'q');
    hymm::core::writeGzFileAtomically(p, payload);
    gzFile f = gzopen(p.c_str(), "rb");
    ASSERT_TRUE(f);
    std::string back(payload.size() + 10, '\0');
    const int n = gzread(f, back.data(), static_cast<unsigned>(back.size()));
    gzclose(f);
    back.resize(static_cast<size_t>(std::max(n, 0)));
    EXPECT_EQ(back, payload);
}

TEST(OutputFilesTest, UncommittedTextFileWritesNothing)
{
    const auto d = freshDir("text");
    {
        AtomicTextFile f((d / "t.txt").string());
        f << "half";
    }
    EXPECT_FALSE(fs::exists(d / "t.txt"));
    AtomicTextFile g((d / "t.txt").string());
    g << "whole " << 42;
    g.commit();
    EXPECT_EQ(slurp(d / "t.txt"), "whole 42");
}

TEST(OutputFolderTest, RunReplacesTheEarlierRunsResultsOnly)
{
    const auto d = freshDir("folder");
    std::ofstream(d / "notes.txt") << "user file";
    {
        OutputFolder out(d.string());
        out.prepare();
        hymm::core::writeFileAtomically(out.staging() + "metrics.json", "{}");
        hymm::core::writeFileAtomically(out.staging() + "map.png", "png");
        EXPECT_FALSE(fs::exists(d / "metrics.json")) << "visible before commit";
        const auto names = out.commit();
        EXPECT_EQ(names, (std::vector<std::string>{"map.png", "metrics.json"}));
    }
    EXPECT_EQ(slurp(d / "metrics.json"), "{}");
    {
        // A second run that writes less: the first run's extra file goes.
        OutputFolder out(d.string());
        out.prepare();
        EXPECT_FALSE(fs::exists(d / "metrics.json"));
        EXPECT_FALSE(fs::exists(d / "map.png"));
        hymm::core::writeFileAtomically(out.staging() + "map.png", "png2");
        out.commit();
    }
    EXPECT_EQ(slurp(d / "map.png"), "png2");
    EXPECT_FALSE(fs::exists(d / "metrics.json"));
    EXPECT_EQ(slurp(d / "notes.txt"), "user file");
    for (const auto& e : fs::directory_iterator(d))
        EXPECT_EQ(e.path().filename().string().find(".hymm-partial"), std::string::npos);
}

TEST(OutputFolderTest, FailedRunLeavesNoResults)
{
    const auto d = freshDir("failed");
    {
        OutputFolder out(d.string());
        out.prepare();
        hymm::core::writeFileAtomically(out.staging() + "path.tum", "1 2 3");
        // no commit: the run failed
    }
    EXPECT_TRUE(fs::is_empty(d));
}

TEST(OutputFolderTest, RefusesFilesAndMissingParents)
{
    const auto d = freshDir("refuse");
    std::ofstream(d / "file") << "x";
    OutputFolder a((d / "file").string());
    EXPECT_NE(errorOf([&] { a.prepare(); }).find("not a folder"), std::string::npos);
    OutputFolder b((d / "missing" / "out").string());
    EXPECT_NE(errorOf([&] { b.prepare(); }).find((d / "missing" / "out").string()), std::string::npos);
    OutputFolder c((d / "new").string());
    c.prepare();
    EXPECT_TRUE(fs::is_directory(d / "new"));
}

TEST(OutputFolderTest, UnwritableFolderIsRefused)
{
    if (::geteuid() == 0) GTEST_SKIP() << "root writes anywhere";
    const auto d = freshDir("ro");
    fs::permissions(d, fs::perms::owner_read | fs::perms::owner_exec);
    OutputFolder out(d.string());
    const std::string err = errorOf([&] { out.prepare(); });
    fs::permissions(d, fs::perms::owner_all);
    EXPECT_NE(err.find("not writable"), std::string::npos) << err;
}

}  // namespace
