#include <gtest/gtest.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/sim/run_scenario.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <fstream>
#include <iterator>
#include <string>

#include "test_scenarios.h"

namespace
{
using hymm::sim::testing::loadScenario;

std::string tempDir(const std::string& tag)
{
    const std::string d = std::string(HYMM_BINARY_DIR) + "/test_out/sim_" + tag;
    mrpt::system::deleteFilesInDirectory(d);
    mrpt::system::createDirectory(std::string(HYMM_BINARY_DIR) + "/test_out");
    mrpt::system::createDirectory(d);
    return d;
}

std::string fileBytes(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

hymm::sim::Scenario shortScenario() { return loadScenario({{"Scenario", "duration_s", "15"}}); }

TEST(RawlogTest, SameSeedSameBytesOtherSeedOtherBytes)
{
    auto s = shortScenario();
    const auto a = hymm::sim::runScenario(s, tempDir("det_a"), false);
    const auto b = hymm::sim::runScenario(s, tempDir("det_b"), false);
    s.run.seed = 8;
    const auto c = hymm::sim::runScenario(s, tempDir("det_c"), false);
    ASSERT_EQ(a.files.size(), b.files.size());
    for (size_t i = 0; i < a.files.size(); ++i)
    {
        const std::string bytes = fileBytes(a.files[i]);
        EXPECT_FALSE(bytes.empty()) << a.files[i];
        EXPECT_EQ(bytes, fileBytes(b.files[i])) << a.files[i];
    }
    EXPECT_NE(fileBytes(a.files[0]), fileBytes(c.files[0]));  // the rawlog
    EXPECT_EQ(fileBytes(a.files[1]), fileBytes(c.files[1]));  // true path: noise-free
    EXPECT_NE(fileBytes(a.files[2]), fileBytes(c.files[2]));  // dead reckoning
}

TEST(RawlogTest, EffectiveConfigReloadsToTheSameRun)
{
    const auto s = shortScenario();
    const auto a = hymm::sim::runScenario(s, tempDir("cfg_a"), false);
    const auto b = hymm::sim::runScenarioFile(a.files[5], tempDir("cfg_b"), std::nullopt, false);
    EXPECT_EQ(fileBytes(a.files[0]), fileBytes(b.files[0]));
    EXPECT_EQ(fileBytes(a.files[5]), fileBytes(b.files[5]));
}

TEST(RawlogTest, RoundTripThroughMrptRawlogReaders)
{
    const auto s = shortScenario();
    const auto sum = hymm::sim::runScenario(s, tempDir("rt"), true);
    const auto gt = hymm::io::readTum(sum.files[1]);
    const auto dr = hymm::io::readTum(sum.files[2]);
    ASSERT_EQ(sum.frames, 76u);  // 15 s at 0.2 s, both ends included
    ASSERT_EQ(gt.size(), sum.frames);
    ASSERT_EQ(dr.size(), sum.frames);
    EXPECT_TRUE(mrpt::system::fileExists(sum.files.back()));  // the PNG

    // 1. CRawlog::loadFromRawLogFile: alternating actions and sensory frames.
    mrpt::obs::CRawlog rawlog;
    ASSERT_TRUE(rawlog.loadFromRawLogFile(sum.files[0]));
    ASSERT_EQ(rawlog.size(), 2 * sum.frames);
    mrpt::poses::CPose2D composed(dr[0].x, dr[0].y, dr[0].phi);
    for (size_t k = 0; k < sum.frames; ++k)
    {
        ASSERT_EQ(rawlog.getType(2 * k), mrpt::obs::CRawlog::etActionCollection);
        ASSERT_EQ(rawlog.getType(2 * k + 1), mrpt::obs::CRawlog::etSensoryFrame);
        const auto acts = rawlog.getAsAction(2 * k);
        const auto mov = acts->getBestMovementEstimation();
        ASSERT_TRUE(mov);
        EXPECT_NEAR(mrpt::Clock::toDouble(mov->timestamp), gt[k].t, 1e-6);
        const auto* gauss =
            dynamic_cast<const mrpt::poses::CPosePDFGaussian*>(mov->poseChange.get());
        ASSERT_NE(gauss, nullptr);
        EXPECT_GT(gauss->cov.det(), 0.0);
        composed = composed + gauss->mean;
        EXPECT_NEAR(composed.x(), dr[k].x, 1e-6) << "frame " << k;
        EXPECT_NEAR(composed.y(), dr[k].y, 1e-6) << "frame " << k;

        const auto sf = rawlog.getAsObservations(2 * k + 1);
        ASSERT_EQ(sf->size(), 2u);
        const auto scan = sf->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
        const auto det = sf->getObservationByClass<mrpt::obs::CObservationBearingRange>();
        ASSERT_TRUE(scan);
        ASSERT_TRUE(det);
        EXPECT_EQ(scan->getScanSize(), 181u);
        EXPECT_NEAR(mrpt::Clock::toDouble(scan->timestamp), gt[k].t, 1e-6);
        EXPECT_NEAR(mrpt::Clock::toDouble(det->timestamp), gt[k].t, 1e-6);
        EXPECT_NEAR(gt[k].t - gt[0].t, 0.2 * k, 1e-6);
    }

    // 2. CRawlog::readActionObservationPair, streaming.
    mrpt::io::CFileGZInputStream in(sum.files[0]);
    auto arch = mrpt::serialization::archiveFrom(in);
    mrpt::obs::CActionCollection::Ptr acts;
    mrpt::obs::CSensoryFrame::Ptr sf;
    size_t entry = 0, pairs = 0;
    while (mrpt::obs::CRawlog::readActionObservationPair(arch, acts, sf, entry)) ++pairs;
    EXPECT_EQ(pairs, sum.frames);
}

}  // namespace
