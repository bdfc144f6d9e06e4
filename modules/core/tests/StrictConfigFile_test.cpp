// Malformed .ini texts (fuzz-like): each must give a clear ConfigError naming the file and,
// where there is one, the line; none may load silently.
#include <gtest/gtest.h>
#include <hymm/core/OptionTable.h>
#include <hymm/core/StrictConfigFile.h>

#include <cstdio>
#include <fstream>
#include <random>

namespace
{
using namespace hymm::core;

struct Opts
{
    double x = 1.0;
    int n = 2;
    OptionTable table()
    {
        OptionTable t;
        t.real("x", x, "m", above(0, 100), "a length");
        t.integer("n", n, "", 0, 10, "a count");
        return t;
    }
};

// Opens `text` strictly, loads [S] and checks every section is known; "" on success.
std::string errorOf(const std::string& text)
{
    try
    {
        const auto f = StrictConfigFile::fromText(text, "test.ini");
        Opts o;
        f.load([&](const auto& cfg) { o.table().load(cfg, "S"); });
        f.checkAllSectionsKnown();
    }
    catch (const ConfigError& e)
    {
        return e.what();
    }
    return "";
}

void expectError(const std::string& text, const std::string& part)
{
    const std::string e = errorOf(text);
    EXPECT_NE(e.find("config file 'test.ini'"), std::string::npos) << "text: " << text << "\nerror: " << e;
    EXPECT_NE(e.find(part), std::string::npos) << "text: " << text << "\nerror: " << e;
}

TEST(StrictConfigFileTest, AWellFormedFileLoads)
{
    EXPECT_EQ(errorOf("; comment\n# other\n[S]\nx = 3  \nn=4\n\n"), "");
}

TEST(StrictConfigFileTest, EmptyOrCommentsOnlyOrSectionlessAreErrors)
{
    expectError("", "holds no [section]");
    expectError("\n\n   \n", "holds no [section]");
    expectError("; just a comment\n# and another\n", "holds no [section]");
    expectError("x = 3\n", "line 1: key 'x' is outside any [section]");
}

TEST(StrictConfigFileTest, BinaryGarbageIsAnError)
{
    expectError(std::string("[S]\nx = 1\n\0\0\x01garbage", 17), "line 3: binary content");
    expectError("\x7f" "ELF\x02\x01\x01", "line 1: binary content");
}

TEST(StrictConfigFileTest, DuplicatesAreErrorsWithBothLines)
{
    expectError("[S]\nx = 1\nx = 2\n", "line 3: duplicate key 'x' in [S] (first at line 2)");
    expectError("[S]\nx = 1\n[S]\nn = 2\n", "line 3: duplicate section [S] (first at line 1)");
}

TEST(StrictConfigFileTest, UnknownAndEmptySectionsAreErrors)
{
    expectError("[S]\nx = 1\n[Ss]\nx = 1\n", "line 3: unknown section [Ss]");
    expectError("[S]\nx = 1\n[T]\n", "line 3: section [T] holds no key");
}

TEST(StrictConfigFileTest, MalformedLinesAreErrors)
{
    expectError("[S]\nx 1\n", "line 2: not a 'key = value' line");
    expectError("[S\nx = 1\n", "line 1: malformed section header");
    expectError("[S]\n= 1\n", "line 2: key name missing");
}

TEST(StrictConfigFileTest, ValueErrorsGetFileAndLine)
{
    expectError("[S]\nn = 1\nx = 1e308\n", "line 3: [S] x=1e308: out of range, must be (0, 100]");
    expectError("[S]\nn = 5000000000\n", "line 2: [S] n=5000000000: out of range");
    expectError("[S]\nxx = 1\n", "line 2: [S] unknown key 'xx'");
}

TEST(StrictConfigFileTest, MissingOrUnreadableFileIsAnError)
{
    try
    {
        StrictConfigFile f("/nonexistent/dir/none.ini");
        FAIL() << "no exception";
    }
    catch (const ConfigError& e)
    {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/none.ini"), std::string::npos);
    }
    // A directory is not readable as a file.
    EXPECT_THROW(StrictConfigFile f("/"), ConfigError);
}

TEST(StrictConfigFileTest, RandomMutationsNeverLoadGarbageSilently)
{
    // Random bytes spliced into a valid file: either it still parses to the same keys
    // (a mutation inside a comment) or it is a ConfigError; never another exception type.
    const std::string base = "; c\n[S]\nx = 3\nn = 4\n";
    std::mt19937 rng(7);
    for (int i = 0; i < 2000; ++i)
    {
        std::string t = base;
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits; ++e)
        {
            const size_t pos = rng() % (t.size() + 1);
            const char c = static_cast<char>(rng() % 256);
            if (rng() % 2) t.insert(t.begin() + static_cast<long>(pos), c);
            else if (pos < t.size()) t[pos] = c;
        }
        try
        {
            const auto f = StrictConfigFile::fromText(t, "m.ini");
            Opts o;
            f.load([&](const auto& cfg) { o.table().load(cfg, "S"); });
            f.checkAllSectionsKnown();
            EXPECT_TRUE(o.x > 0 && o.x <= 100 && o.n >= 0 && o.n <= 10) << t;
        }
        catch (const ConfigError&)
        {
        }
    }
}

}  // namespace
