#include <gtest/gtest.h>
#include <hymm/core/config_utils.h>
#include <mrpt/config/CConfigFileMemory.h>

namespace
{
using namespace hymm::core;

TEST(ConfigUtilsTest, ReadsTypedValues)
{
    mrpt::config::CConfigFileMemory cfg("[S]\nx = 2.5\nn = 7\nflag = true\nlist = 1, 2 3\n");
    EXPECT_DOUBLE_EQ(readDouble(cfg, "S", "x", 0), 2.5);
    EXPECT_EQ(readInt(cfg, "S", "n", 0), 7);
    EXPECT_TRUE(readBool(cfg, "S", "flag", false));
    EXPECT_EQ(readDoubleList(cfg, "S", "list", {}), (std::vector<double>{1, 2, 3}));
    EXPECT_DOUBLE_EQ(readDouble(cfg, "S", "absent", 4.0), 4.0);
}

TEST(ConfigUtilsTest, MalformedValuesAreErrorsNamingTheKey)
{
    mrpt::config::CConfigFileMemory cfg("[S]\nx = abc\nn = 3.5\nsigma = -1\nflag = maybe\n");
    try
    {
        readDouble(cfg, "S", "x", 0);
        FAIL() << "no exception";
    }
    catch (const std::invalid_argument& e)
    {
        EXPECT_NE(std::string(e.what()).find("[S] x=abc"), std::string::npos) << e.what();
    }
    EXPECT_THROW(readInt(cfg, "S", "n", 0), std::invalid_argument);
    EXPECT_THROW(readDoubleMin(cfg, "S", "sigma", 0, 0.0, false), std::invalid_argument);
    EXPECT_THROW(readBool(cfg, "S", "flag", false), std::invalid_argument);
    EXPECT_THROW(readDouble(cfg, "S", "missing", 0, true), std::invalid_argument);
}

TEST(ConfigUtilsTest, UnknownKeysAreRejected)
{
    mrpt::config::CConfigFileMemory cfg("[S]\nalpha = 1\nbetta = 2\n");
    EXPECT_NO_THROW(checkKnownKeys(cfg, "S", {"alpha", "betta"}));
    EXPECT_THROW(checkKnownKeys(cfg, "S", {"alpha", "beta"}), std::invalid_argument);
}

TEST(ConfigUtilsTest, MissingFileIsAClearError)
{
    try
    {
        openConfigFile("/nonexistent/dir/file.ini");
        FAIL() << "no exception";
    }
    catch (const std::invalid_argument& e)
    {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/file.ini"), std::string::npos);
    }
}

}  // namespace
