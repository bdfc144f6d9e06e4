// The sample rawlogs in rawlogs/ are readable, small, and were made from the shipped
// scenario configs as they are now (else: run scripts/make-sample-rawlogs).
#include <gtest/gtest.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/sim/Scenario.h>
#include <mrpt/obs/CRawlog.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace
{
std::string readText(const std::string& path)
{
    std::ifstream f(path);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

class SampleRawlogTest : public ::testing::TestWithParam<std::string>
{
};

TEST_P(SampleRawlogTest, IsSmallReadableAndMatchesItsConfig)
{
    const std::string name = GetParam();
    const std::string base = std::string(HYMM_SOURCE_DIR) + "/rawlogs/" + name;
    const std::string rawlog_path = base + ".rawlog";
    ASSERT_TRUE(std::filesystem::exists(rawlog_path)) << rawlog_path;
    EXPECT_LT(std::filesystem::file_size(rawlog_path), 3u << 20);

    mrpt::obs::CRawlog rawlog;
    ASSERT_TRUE(rawlog.loadFromRawLogFile(rawlog_path));
    const auto gt = hymm::io::readTum(base + "_gt_path.tum");
    ASSERT_GT(gt.size(), 100u);
    EXPECT_EQ(rawlog.size(), 2 * gt.size());

    // The effective config stored with the sample is the shipped config's.
    const auto scenario = hymm::sim::Scenario::fromFile(std::string(HYMM_SOURCE_DIR) +
                                                        "/configs/sim/" + name + ".ini");
    const std::string stored = readText(base + "_config.ini");
    EXPECT_NE(stored.find(scenario.toIniText()), std::string::npos)
        << "rawlogs/" << name << " is stale: run scripts/make-sample-rawlogs";
}

INSTANTIATE_TEST_SUITE_P(Samples, SampleRawlogTest,
                         ::testing::Values("ch3_objects", "ch2_landmarks"));

}  // namespace
