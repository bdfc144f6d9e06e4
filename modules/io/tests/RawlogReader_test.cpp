#include <gtest/gtest.h>
#include <hymm/io/RawlogReader.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <fstream>
#include <iterator>

namespace
{
using hymm::io::RawlogEntry;
using hymm::io::RawlogReader;

// Writes `frames` action/sensory-frame pairs (actions-SF rawlog format).
std::string writeSampleRawlog(size_t frames, bool gz = true)
{
    const std::string path = mrpt::system::getTempFileName() + ".rawlog";
    std::unique_ptr<mrpt::io::CStream> out;
    if (gz)
        out = std::make_unique<mrpt::io::CFileGZOutputStream>(path);
    else
        out = std::make_unique<mrpt::io::CFileOutputStream>(path);
    auto arch = mrpt::serialization::archiveFrom(*out);
    for (size_t i = 0; i < frames; ++i)
    {
        mrpt::obs::CActionCollection acts;
        mrpt::obs::CActionRobotMovement2D mov;
        mrpt::obs::CActionRobotMovement2D::TMotionModelOptions opts;
        mov.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0, 0.01), opts);
        acts.insert(mov);
        arch << acts;
        mrpt::obs::CSensoryFrame sf;
        auto obs = mrpt::obs::CObservationBearingRange::Create();
        obs->timestamp = mrpt::Clock::fromDouble(100.0 + i);
        mrpt::obs::CObservationBearingRange::TMeasurement m;
        m.range = 5.0;
        m.yaw = 0.3;
        m.landmarkID = 7;
        obs->sensedData.push_back(m);
        sf.insert(obs);
        arch << sf;
    }
    return path;
}

size_t countEntries(const std::string& path)
{
    RawlogReader r(path);
    RawlogEntry e;
    while (r.next(e))
    {
    }
    return r.entriesRead();
}

TEST(RawlogReaderTest, ReadsActionsAndFramesInOrder)
{
    const auto path = writeSampleRawlog(3);
    RawlogReader r(path);
    RawlogEntry e;
    for (size_t i = 0; i < 3; ++i)
    {
        ASSERT_TRUE(r.next(e));
        ASSERT_TRUE(e.actions);
        EXPECT_FALSE(e.frame);
        ASSERT_TRUE(r.next(e));
        ASSERT_TRUE(e.frame);
        auto obs = e.frame->getObservationByClass<mrpt::obs::CObservationBearingRange>();
        ASSERT_TRUE(obs);
        EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(obs->timestamp), 100.0 + i);
    }
    EXPECT_FALSE(r.next(e));
    EXPECT_EQ(r.entriesRead(), 6u);
}

TEST(RawlogReaderTest, ReadsUncompressedRawlogs)
{
    EXPECT_EQ(countEntries(writeSampleRawlog(2, false)), 4u);
}

TEST(RawlogReaderTest, MissingFileIsAnErrorNamingThePath)
{
    try
    {
        RawlogReader r("/nonexistent/x.rawlog");
        FAIL() << "no exception";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/x.rawlog"), std::string::npos);
    }
}

TEST(RawlogReaderTest, TruncatedFileIsAnErrorNotAShortLog)
{
    const auto good = writeSampleRawlog(4, false);
    std::ifstream in(good, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string cut = mrpt::system::getTempFileName() + ".rawlog";
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 20);
    EXPECT_THROW(countEntries(cut), std::runtime_error);
}

TEST(RawlogReaderTest, GarbageFileIsAnError)
{
    const std::string path = mrpt::system::getTempFileName() + ".rawlog";
    std::ofstream(path) << "this is not a rawlog, just some text that goes on for a while\n";
    EXPECT_THROW(countEntries(path), std::runtime_error);
}

TEST(RawlogReaderTest, EmptyFileHasNoEntries)
{
    const std::string path = mrpt::system::getTempFileName() + ".rawlog";
    std::ofstream(path).close();
    EXPECT_EQ(countEntries(path), 0u);
}

}  // namespace
