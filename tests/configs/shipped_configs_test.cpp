#include <gtest/gtest.h>
#include <hymm/core/config_utils.h>
#include <hymm/denseslam/DenseSlam.h>

#include <filesystem>
#include <fstream>

namespace
{
TEST(ShippedConfigsTest, EveryPipelineConfigLoads)
{
    const std::filesystem::path dir = std::filesystem::path(HYMM_SOURCE_DIR) / "configs";
    size_t n = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir))
    {
        if (e.path().extension() != ".ini") continue;
        SCOPED_TRACE(e.path().string());
        EXPECT_NO_THROW(hymm::denseslam::DenseSlam::fromConfig(*hymm::core::openConfigFile(e.path())));
        ++n;
    }
    EXPECT_GE(n, 5u);
}

TEST(ShippedConfigsTest, TypoInAKeyIsRejected)
{
    const auto path = std::filesystem::temp_directory_path() / "hymm_typo.ini";
    {
        std::ofstream f(path);
        f << "[DenseSlam]\nlandmark_sorce = bearing_range\n";
    }
    EXPECT_THROW(hymm::denseslam::DenseSlam::fromConfig(*hymm::core::openConfigFile(path)),
                 std::invalid_argument);
}

}  // namespace
