#include <gtest/gtest.h>
#include <hymm/core/OptionTable.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>

namespace
{
using namespace hymm::core;

enum class Mode
{
    A,
    B
};

struct Opts
{
    double gain = 0.5;
    double angle = 2.0 * M_PI / 180.0;
    int count = 3;
    size_t budget = 100;
    bool on = true;
    Mode mode = Mode::A;
    std::string name = "x";

    OptionTable table()
    {
        OptionTable t;
        t.real("gain", gain, "", openInterval(0, 1), "a probability");
        t.degrees("angle_deg", angle, atLeast(0, 90), "an angle");
        t.integer("count", count, "", 1, 1000, "a count");
        t.integer("budget", budget, "", 0, 1000000, "a budget");
        t.flag("on", on, "a switch");
        t.choice("mode", mode, {{"a", Mode::A}, {"b", Mode::B}}, "a mode");
        t.text("name", name, "a name");
        return t;
    }
};

std::string errorOf(const std::string& ini)
{
    mrpt::config::CConfigFileMemory cfg(ini);
    Opts o;
    try
    {
        o.table().load(cfg, "S");
    }
    catch (const ConfigError& e)
    {
        return e.what();
    }
    return "";
}

TEST(OptionTableTest, LoadsPresentKeysAndKeepsDefaultsOfAbsentOnes)
{
    mrpt::config::CConfigFileMemory cfg("[S]\ngain = 0.25\nangle_deg = 45\nbudget = 7\nmode = b\n");
    Opts o;
    o.table().load(cfg, "S");
    EXPECT_EQ(o.gain, 0.25);
    EXPECT_EQ(o.angle, 45 * M_PI / 180.0);
    EXPECT_EQ(o.budget, 7u);
    EXPECT_EQ(o.mode, Mode::B);
    EXPECT_EQ(o.count, 3);  // absent: unchanged
    EXPECT_TRUE(o.on);
    EXPECT_EQ(o.name, "x");
}

TEST(OptionTableTest, SaveThenLoadRoundTrips)
{
    Opts a;
    a.gain = 0.1;
    a.angle = 0.3;
    a.count = 999;
    a.on = false;
    a.mode = Mode::B;
    a.name = "hello";
    mrpt::config::CConfigFileMemory cfg;
    a.table().save(cfg, "S");
    Opts b;
    b.table().load(cfg, "S");
    EXPECT_EQ(b.gain, a.gain);
    EXPECT_NEAR(b.angle, a.angle, 1e-15);
    EXPECT_EQ(b.count, a.count);
    EXPECT_EQ(b.on, a.on);
    EXPECT_EQ(b.mode, a.mode);
    EXPECT_EQ(b.name, a.name);
}

TEST(OptionTableTest, ErrorsNameSectionKeyAndValueAsWritten)
{
    EXPECT_NE(errorOf("[S]\ngain = 1.0\n").find("[S] gain=1.0: out of range, must be (0, 1)"),
              std::string::npos);
    // An out-of-range integer is reported as written, never truncated or wrapped.
    EXPECT_NE(errorOf("[S]\ncount = 5000000000\n").find("[S] count=5000000000: out of range"),
              std::string::npos);
    EXPECT_NE(errorOf("[S]\ncount = 99999999999999999999999\n").find("count=99999999999999999999999"),
              std::string::npos);
    EXPECT_NE(errorOf("[S]\nbudget = -1\n").find("[S] budget=-1: out of range"), std::string::npos);
    EXPECT_NE(errorOf("[S]\ncount = 2.5\n").find("not an integer"), std::string::npos);
    EXPECT_NE(errorOf("[S]\ngain = 1e400\n").find("[S] gain=1e400: not a number"), std::string::npos);
    EXPECT_NE(errorOf("[S]\ngain = nan\n").find("must be finite"), std::string::npos);
    EXPECT_NE(errorOf("[S]\ngain = 0.5x\n").find("not a number"), std::string::npos);
    EXPECT_NE(errorOf("[S]\nangle_deg = 91\n").find("[S] angle_deg=91: out of range, must be [0, 90]"),
              std::string::npos);
    EXPECT_NE(errorOf("[S]\nmode = c\n").find("must be one of a, b"), std::string::npos);
    EXPECT_NE(errorOf("[S]\non = maybe\n").find("not a boolean"), std::string::npos);
    EXPECT_NE(errorOf("[S]\ngian = 0.5\n").find("unknown key 'gian'"), std::string::npos);
    EXPECT_EQ(errorOf("[S]\ngain = 0.999\ncount = 1000\n"), "");
}

TEST(OptionTableTest, MarkdownListsEveryKeyWithDefaultAndRange)
{
    Opts o;
    const std::string md = o.table().markdown();
    EXPECT_NE(md.find("| `gain` |  | `0.5` | (0, 1) | a probability |"), std::string::npos) << md;
    EXPECT_NE(md.find("| `angle_deg` | deg | `2` | [0, 90] | an angle |"), std::string::npos) << md;
    EXPECT_NE(md.find("| `count` |  | `3` | integer in [1, 1000] | a count |"), std::string::npos) << md;
    EXPECT_NE(md.find("`a` \\| `b`"), std::string::npos) << md;
}

TEST(OptionTableTest, DeclaringAKeyTwiceIsAProgrammingError)
{
    double a = 0, b = 0;
    OptionTable t;
    t.real("k", a, "", atLeast(0), "");
    EXPECT_THROW(t.real("k", b, "", atLeast(0), ""), std::logic_error);
}

TEST(OptionTableTest, FormatRealIsShortestExact)
{
    EXPECT_EQ(formatReal(0.1), "0.1");
    EXPECT_EQ(formatReal(0.9999), "0.9999");
    EXPECT_EQ(formatReal(1e-6), "1e-06");
    const double x = 1.0 / 3.0;
    EXPECT_EQ(std::strtod(formatReal(x).c_str(), nullptr), x);
}

}  // namespace
