#include <gtest/gtest.h>
#include <hymm/core/config_utils.h>
#include <hymm/datasets/CarParkImporter.h>
#include <hymm/datasets/MrclamImporter.h>
#include <hymm/datasets/VictoriaParkImporter.h>
#include <hymm/datasets/import_dataset.h>

#include "test_files.h"

namespace
{
using hymm::datasets::testing::TempDir;
using hymm::datasets::testing::writeText;

const std::string kConfigs = std::string(HYMM_SOURCE_DIR) + "/configs/datasets/";

TEST(ImportDatasetTest, ShippedConfigsLoadWithTheirDefaults)
{
    hymm::datasets::VictoriaParkImporter::Options vp;
    vp.loadFromConfigFile(*hymm::core::openConfigFile(kConfigs + "victoria_park.ini"),
                          "VictoriaParkImporter");
    EXPECT_DOUBLE_EQ(vp.vehicle.a, 3.78);
    EXPECT_DOUBLE_EQ(vp.detections_time_offset_s, 20.967);
    hymm::datasets::CarParkImporter::Options cp;
    cp.loadFromConfigFile(*hymm::core::openConfigFile(kConfigs + "carpark.ini"),
                          "CarParkImporter");
    EXPECT_DOUBLE_EQ(cp.vehicle.a, 3.78);
    hymm::datasets::MrclamImporter::Options mr;
    mr.loadFromConfigFile(*hymm::core::openConfigFile(kConfigs + "mrclam.ini"), "MrclamImporter");
    EXPECT_EQ(mr.robot, 1);
    EXPECT_DOUBLE_EQ(mr.sample_period_s, 0.02);
}

TEST(ImportDatasetTest, ConfigTyposAndMissingFilesAreReportedByName)
{
    TempDir dir;
    writeText(dir.file("bad.ini"), "[MrclamImporter]\nrobots = 2\n");
    try
    {
        hymm::datasets::importDataset("mrclam", {dir.path()}, dir.file("out"),
                                      dir.file("bad.ini"));
        FAIL() << "no exception";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("robots"), std::string::npos) << e.what();
    }
    EXPECT_THROW(hymm::datasets::importDataset("carpark", {dir.path()}, dir.file("out"),
                                               dir.file("absent.ini")),
                 std::exception);
}

TEST(ImportDatasetTest, InputsAreFoundAsFilesOrInFolders)
{
    TempDir dir;
    writeText(dir.file("Barcodes.dat"), "1 5\n");
    using hymm::datasets::findInputFile;
    EXPECT_EQ(findInputFile({dir.path()}, "Barcodes.dat", true), dir.file("Barcodes.dat"));
    EXPECT_EQ(findInputFile({dir.file("Barcodes.dat")}, "Barcodes.dat", true),
              dir.file("Barcodes.dat"));
    EXPECT_EQ(findInputFile({dir.path()}, "Other.dat", false), "");
    EXPECT_THROW(findInputFile({dir.file("sub/Barcodes.dat")}, "Barcodes.dat", true),
                 std::runtime_error);
}

}  // namespace
