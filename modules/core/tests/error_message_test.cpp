#include <gtest/gtest.h>
#include <hymm/core/error_message.h>
#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace
{
std::string mrptError()
{
    try
    {
        THROW_EXCEPTION("Cannot read object header from stream! (EOF?)");
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return {};
}

TEST(ErrorMessageTest, BacktraceOnlyWhenVerbose)
{
    const std::string inner = mrptError();
    ASSERT_NE(inner.find("Call stack backtrace:"), std::string::npos) << "MRPT built without call stacks?";
    // As RawlogReader wraps it: our message, then MRPT's text.
    const std::runtime_error e("rawlog 'x.rawlog' is corrupt at entry 3: " + inner);
    const std::string quiet = hymm::core::errorMessage(e, false);
    EXPECT_EQ(quiet.find("Call stack backtrace"), std::string::npos) << quiet;
    EXPECT_EQ(quiet.find("===="), std::string::npos) << quiet;
    EXPECT_NE(quiet.find("rawlog 'x.rawlog' is corrupt at entry 3: "), std::string::npos) << quiet;
    EXPECT_NE(quiet.find("Cannot read object header from stream!"), std::string::npos) << quiet;
    EXPECT_LE(std::count(quiet.begin(), quiet.end(), '\n'), 1) << quiet;
    const std::string verbose = hymm::core::errorMessage(e, true);
    EXPECT_NE(verbose.find("Call stack backtrace"), std::string::npos);
}

TEST(ErrorMessageTest, PlainErrorsPassUnchanged)
{
    const std::invalid_argument e("[DenseSlam] landmark_source: 'x' is not valid");
    EXPECT_EQ(hymm::core::errorMessage(e, false), e.what());
}

TEST(ErrorMessageTest, VerboseFlagIsFoundAnywhere)
{
    const char* argv[] = {"app", "-c", "x.ini", "--verbose"};
    EXPECT_TRUE(hymm::core::hasFlag(4, const_cast<char**>(argv), "--verbose"));
    EXPECT_FALSE(hymm::core::hasFlag(3, const_cast<char**>(argv), "--verbose"));
}

}  // namespace
