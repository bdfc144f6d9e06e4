#include <gtest/gtest.h>
#include <hymm/datasets/MatFile.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "test_files.h"

namespace
{
using hymm::datasets::MatFile;
using hymm::datasets::testing::TempDir;

TEST(MatFileTest, RoundTripsMatricesAndVectorsThroughMatlabV5)
{
    TempDir dir;
    Eigen::MatrixXd a(3, 2);
    a << 1, 2, 3, 4, 5, 6.5;
    Eigen::MatrixXd v(1, 4);
    v << -1, 0, 1e-9, 1e9;
    hymm::datasets::writeMatFile(dir.file("x.mat"), {{"a", a}, {"v", v}});

    const MatFile f(dir.file("x.mat"));
    const auto names = f.variableNames();
    EXPECT_NE(std::find(names.begin(), names.end(), "a"), names.end());
    EXPECT_NE(std::find(names.begin(), names.end(), "v"), names.end());
    EXPECT_TRUE(f.hasVariable("a"));
    EXPECT_FALSE(f.hasVariable("nope"));
    EXPECT_EQ(f.readMatrix("a"), a);  // row/column layout kept
    const Eigen::VectorXd vv = f.readVector("v");
    ASSERT_EQ(vv.size(), 4);
    EXPECT_EQ(vv[3], 1e9);
    EXPECT_THROW(f.readVector("a"), std::runtime_error);
}

TEST(MatFileTest, MissingFileAndVariableGiveMessagesNamingThem)
{
    TempDir dir;
    try
    {
        MatFile f(dir.file("absent.mat"));
        FAIL() << "no exception";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("absent.mat"), std::string::npos);
    }
    hymm::datasets::writeMatFile(dir.file("x.mat"), {{"a", Eigen::MatrixXd::Ones(2, 2)}});
    const MatFile f(dir.file("x.mat"));
    try
    {
        f.readMatrix("speed");
        FAIL() << "no exception";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("'speed'"), std::string::npos);
    }
}

std::vector<char> readBytes(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::vector<char>& b)
{
    std::ofstream(path, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
}

void expectRefused(const std::string& path, const std::string& what)
{
    try
    {
        const MatFile f(path);
        (void)f.readMatrix("a");
        FAIL() << "accepted: " << what;
    }
    catch (const std::runtime_error& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find(path), std::string::npos) << m;
        EXPECT_NE(m.find(what), std::string::npos) << m;
    }
}

TEST(MatFileTest, DeclaredSizesBeyondTheFileAreRefusedBeforeMatioAllocates)
{
    // The fuzz finding: a dimensions element declaring 926 million entries made libmatio
    // allocate a 7 GB dimensions array for a file of 11 kB. Offsets of writeMatFile's
    // uncompressed layout: header (128), matrix tag (8), array flags (16), dimensions tag.
    TempDir dir;
    Eigen::MatrixXd a(20, 1);
    a.setOnes();
    hymm::datasets::writeMatFile(dir.file("ok.mat"), {{"a", a}});
    const auto ok = readBytes(dir.file("ok.mat"));
    const auto put = [](std::vector<char> b, size_t at, uint32_t v) {
        std::memcpy(&b[at], &v, 4);
        return b;
    };
    uint32_t dims_type = 0, dims_bytes = 0, rows = 0;
    std::memcpy(&dims_type, &ok[152], 4);
    std::memcpy(&dims_bytes, &ok[156], 4);
    std::memcpy(&rows, &ok[160], 4);
    ASSERT_EQ(dims_type, 5u);  // miINT32
    ASSERT_EQ(dims_bytes, 8u);
    ASSERT_EQ(rows, 20u);
    EXPECT_EQ(MatFile(dir.file("ok.mat")).readMatrix("a"), a);

    writeBytes(dir.file("dims.mat"), put(ok, 156, 926365495u));
    expectRefused(dir.file("dims.mat"), "declares 926365495 bytes");
    // 2^30 rows of doubles held in 160 bytes.
    writeBytes(dir.file("rows.mat"), put(ok, 160, 1u << 30));
    expectRefused(dir.file("rows.mat"), "declares 1073741824 elements");
    // The variable itself longer than the file.
    writeBytes(dir.file("var.mat"), put(ok, 132, 0x80000000u));
    expectRefused(dir.file("var.mat"), "declares 2147483648 bytes");
}

TEST(MatFileTest, CorruptFileIsRejected)
{
    TempDir dir;
    hymm::datasets::testing::writeText(dir.file("bad.mat"), "this is not a MAT file at all\n");
    EXPECT_THROW(MatFile f(dir.file("bad.mat")), std::runtime_error);
}

}  // namespace
