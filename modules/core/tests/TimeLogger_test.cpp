#include <hymm/core/TimeLogger.h>

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <type_traits>

using hymm::core::LazyTimeLogger;
using hymm::core::TimedSection;

// A copied section would stop, and record, the same section twice.
static_assert(!std::is_copy_constructible_v<TimedSection> && !std::is_copy_assignable_v<TimedSection>);

namespace
{
std::map<std::string, mrpt::system::CTimeLogger::TCallStats> statsOf(const LazyTimeLogger& l)
{
    std::map<std::string, mrpt::system::CTimeLogger::TCallStats> s;
    l.get().getStats(s);
    return s;
}
// MRPT's CTimeLogger prints what it holds when destroyed: not in the test output.
void quiet(LazyTimeLogger& l)
{
    l.get().clear(true);
    l.get().disable();
}
}  // namespace

TEST(LazyTimeLoggerTest, DisabledSectionsMakeNoLogger)
{
    LazyTimeLogger l(false, "test");
    {
        TimedSection s(l, "a");
    }
    EXPECT_EQ(l.active(), nullptr);
    // Disabling a logger that does not exist does not make one either.
    l.enable(false);
    EXPECT_EQ(l.active(), nullptr);
    // Asked for, it exists, disabled, and still holds nothing.
    EXPECT_FALSE(l.get().isEnabled());
    EXPECT_EQ(statsOf(l).size(), 0u);
}

TEST(LazyTimeLoggerTest, EnabledSectionsAreTimed)
{
    LazyTimeLogger l(true, "test");
    ASSERT_NE(l.active(), nullptr);
    for (int i = 0; i < 3; ++i)
    {
        TimedSection s(l, "a");
    }
    {
        TimedSection s(l, "b");
        s.stop();
    }
    const auto stats = statsOf(l);
    ASSERT_EQ(stats.count("a"), 1u);
    EXPECT_EQ(stats.at("a").n_calls, 3u);
    ASSERT_EQ(stats.count("b"), 1u);
    EXPECT_EQ(stats.at("b").n_calls, 1u);
    // Enabled after construction, through the accessor the apps use.
    LazyTimeLogger m(false, "later");
    m.get().enable();
    {
        TimedSection s(m, "c");
    }
    EXPECT_EQ(statsOf(m).count("c"), 1u);
    quiet(l);
    quiet(m);
}

TEST(LazyTimeLoggerTest, CopiesAreIndependent)
{
    LazyTimeLogger l(true, "test");
    {
        TimedSection s(l, "a");
    }
    LazyTimeLogger c = l;
    {
        TimedSection s(c, "a");
    }
    EXPECT_EQ(statsOf(l).at("a").n_calls, 1u);
    EXPECT_EQ(statsOf(c).at("a").n_calls, 2u);
    LazyTimeLogger off;
    LazyTimeLogger d = off;
    EXPECT_EQ(d.active(), nullptr);
    d = l;
    EXPECT_EQ(statsOf(d).at("a").n_calls, 1u);
    quiet(l);
    quiet(c);
    quiet(d);
}
