#include <gtest/gtest.h>
#include <hymm/datasets/MatFile.h>

#include <algorithm>

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

TEST(MatFileTest, CorruptFileIsRejected)
{
    TempDir dir;
    hymm::datasets::testing::writeText(dir.file("bad.mat"), "this is not a MAT file at all\n");
    EXPECT_THROW(MatFile f(dir.file("bad.mat")), std::runtime_error);
}

}  // namespace
