// Pseudo ground truth from a corrected CARMEN log: the FLASER reader and the pairing of
// scans by equal ranges, on a rawlog and logs written here.
#include <gtest/gtest.h>
#include <hymm/datasets/CarmenGroundTruth.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <zlib.h>

#include <fstream>
#include <iterator>
#include <sstream>

#include "test_files.h"

namespace
{
using hymm::datasets::CarmenLaserScan;
using hymm::datasets::testing::TempDir;
using hymm::datasets::testing::writeText;

std::vector<double> rangesOf(int k, size_t n = 8)
{
    std::vector<double> r;
    for (size_t i = 0; i < n; ++i) r.push_back(1.0 + 0.01 * static_cast<double>((k * 7 + static_cast<int>(i) * 3) % 97));
    return r;
}

mrpt::obs::CObservation2DRangeScan::Ptr scanOf(const std::vector<double>& r, double t)
{
    auto s = mrpt::obs::CObservation2DRangeScan::Create();
    s->resizeScan(r.size());
    for (size_t i = 0; i < r.size(); ++i)
    {
        s->setScanRange(i, static_cast<float>(r[i]));
        s->setScanRangeValidity(i, true);
    }
    s->aperture = static_cast<float>(M_PI);
    s->timestamp = mrpt::Clock::fromDouble(t);
    return s;
}

/** Scans 0..5 in sensory frames, scan 6 as a lone observation, scan 7 repeats scan 2's ranges. */
void writeRawlog(const std::string& path)
{
    mrpt::obs::CRawlog log;
    for (int k = 0; k < 6; ++k)
    {
        mrpt::obs::CSensoryFrame sf;
        sf.insert(scanOf(rangesOf(k), 100.0 + 0.1 * (k / 3)));  // stamps repeat, as on Intel
        log.insert(sf);
    }
    log.insert(scanOf(rangesOf(6), 101.0));
    mrpt::obs::CSensoryFrame sf;
    sf.insert(scanOf(rangesOf(2), 101.1));
    log.insert(sf);
    ASSERT_TRUE(log.saveToRawLogFile(path));
}

std::string flaser(const std::vector<double>& r, double x, double y, double th, double t)
{
    std::ostringstream o;
    o << "FLASER " << r.size();
    for (double v : r) o << " " << v;
    o << " " << x << " " << y << " " << th << " " << x << " " << y << " " << th << " " << t << " host " << t << "\n";
    return o.str();
}

TEST(CarmenGroundTruth, ReadsFlaserLinesOfPlainAndGzipLogs)
{
    TempDir dir;
    const std::string text = "# message formats\nPARAM robot_frontlaser_offset 0.0 nohost 0\n"
                             "ODOM 0 0 0 0 0 0 0.1 host 0.1\n" +
                             flaser({1.5, 2.25, 3}, 1, -2, 0.5, 7.25) + flaser({4}, 0, 0, -3, 8);
    writeText(dir.file("a.log"), text);
    gzFile gz = gzopen(dir.file("a.log.gz").c_str(), "wb");
    ASSERT_NE(gz, nullptr);
    ASSERT_EQ(gzputs(gz, text.c_str()), static_cast<int>(text.size()));
    gzclose(gz);
    for (const char* f : {"a.log", "a.log.gz"})
    {
        const auto s = hymm::datasets::readCarmenLaserScans(dir.file(f));
        ASSERT_EQ(s.size(), 2u) << f;
        EXPECT_EQ(s[0].ranges, (std::vector<double>{1.5, 2.25, 3}));
        EXPECT_EQ(s[0].pose, Eigen::Vector3d(1, -2, 0.5));
        EXPECT_DOUBLE_EQ(s[0].t, 7.25);
        EXPECT_EQ(s[1].ranges.size(), 1u);
        EXPECT_DOUBLE_EQ(s[1].pose[2], -3);
    }
}

TEST(CarmenGroundTruth, CrlfLongLinesAndAMissingLastNewlineAreRead)
{
    TempDir dir;
    // 20,000 readings make a line of about 100 KiB, longer than the reader's buffer.
    std::vector<double> many(20000, 12.345);
    std::string crlf = flaser({1, 2}, 3, 4, 0.25, 9);
    crlf.insert(crlf.size() - 1, "\r");
    std::string last = flaser({5}, 0, 1, 0, 10);
    last.pop_back();
    writeText(dir.file("a.log"), crlf + flaser(many, 1, 1, 1, 11) + last);
    const auto s = hymm::datasets::readCarmenLaserScans(dir.file("a.log"));
    ASSERT_EQ(s.size(), 3u);
    EXPECT_EQ(s[0].ranges, (std::vector<double>{1, 2}));
    EXPECT_DOUBLE_EQ(s[0].t, 9);
    EXPECT_EQ(s[1].ranges.size(), 20000u);
    EXPECT_DOUBLE_EQ(s[1].ranges.back(), 12.345);
    EXPECT_EQ(s[1].pose, Eigen::Vector3d(1, 1, 1));
    EXPECT_EQ(s[2].ranges, (std::vector<double>{5}));
}

TEST(CarmenGroundTruth, ATruncatedGzipLogIsAReadError)
{
    TempDir dir;
    std::string text;
    for (int k = 0; k < 200; ++k) text += flaser(rangesOf(k, 180), k, 0, 0, k);
    gzFile gz = gzopen(dir.file("a.log.gz").c_str(), "wb");
    ASSERT_NE(gz, nullptr);
    ASSERT_EQ(gzputs(gz, text.c_str()), static_cast<int>(text.size()));
    gzclose(gz);
    std::ifstream in(dir.file("a.log.gz"), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir.file("cut.log.gz"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    EXPECT_EQ(hymm::datasets::readCarmenLaserScans(dir.file("a.log.gz")).size(), 200u);
    try
    {
        hymm::datasets::readCarmenLaserScans(dir.file("cut.log.gz"));
        ADD_FAILURE() << "a truncated log was read";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("read error"), std::string::npos) << e.what();
    }
}

TEST(CarmenGroundTruth, MalformedFlaserLinesAndMissingFilesThrowWithTheLine)
{
    TempDir dir;
    EXPECT_THROW(hymm::datasets::readCarmenLaserScans(dir.file("none.log")), std::runtime_error);
    const std::pair<const char*, const char*> bad[] = {
        {"short", "FLASER 3 1 2 3 0 0 0 0 0 0\n"},                  // no timestamp
        {"count", "FLASER -2 0 0 0 0 0 0 1 h 1\n"},                 // negative count
        {"nan", "FLASER 1 nan 0 0 0 0 0 0 1 h 1\n"},                // NaN range
        {"text", "FLASER 1 1.0 x 0 0 0 0 0 1 h 1\n"},               // pose not a number
        {"huge", "FLASER 1e9 1 0 0 0 0 0 1 h 1\n"},                // a count no laser has
    };
    for (const auto& [name, line] : bad)
    {
        writeText(dir.file(name), "ODOM 0 0 0 0 0 0 0 h 0\n" + std::string(line));
        try
        {
            hymm::datasets::readCarmenLaserScans(dir.file(name));
            ADD_FAILURE() << name << " was accepted";
        }
        catch (const std::runtime_error& e)
        {
            EXPECT_NE(std::string(e.what()).find(":2:"), std::string::npos) << name << ": " << e.what();
        }
    }
}

TEST(CarmenGroundTruth, PairsScansWithEqualRangesOnlyOnceAndInOrder)
{
    TempDir dir;
    writeRawlog(dir.file("a.rawlog"));
    std::vector<CarmenLaserScan> c;
    auto add = [&](std::vector<double> r, double x) {
        CarmenLaserScan s;
        s.ranges = std::move(r);
        s.pose = Eigen::Vector3d(x, 2 * x, 0.1 * x);
        c.push_back(s);
    };
    add(rangesOf(1), 1);  // scan 1
    // Scan 3 within half a centimetre on every beam (the logs print 1 cm): still scan 3.
    auto r3 = rangesOf(3);
    for (auto& v : r3) v += 0.004;
    add(r3, 3);
    auto r4 = rangesOf(4);
    r4[5] += 0.02;  // one beam 2 cm off: no scan
    add(r4, 4);
    add(rangesOf(2), 2);  // twice in the rawlog (scans 2 and 7): ambiguous
    add(rangesOf(0), 0);  // scan 0 after scan 3: out of order
    add(rangesOf(6), 6);  // the lone observation
    add(rangesOf(5, 7), 5);  // a beam fewer: no scan

    const auto p = hymm::datasets::pairScansByRanges(dir.file("a.rawlog"), c);
    EXPECT_EQ(p.rawlog_scans, 8u);
    EXPECT_EQ(p.carmen_scans, 7u);
    EXPECT_EQ(p.unmatched, 2u);
    EXPECT_EQ(p.ambiguous, 1u);
    EXPECT_EQ(p.out_of_order, 1u);
    ASSERT_EQ(p.matches.size(), 3u);
    const size_t want[] = {1, 3, 6};
    for (size_t i = 0; i < 3; ++i)
    {
        EXPECT_EQ(p.matches[i].scan, want[i]);
        EXPECT_EQ(p.matches[i].pose, Eigen::Vector3d(want[i], 2.0 * want[i], 0.1 * want[i]));
    }
    EXPECT_NEAR(p.matches[1].t, 100.1, 1e-6);
    EXPECT_NEAR(p.matches[2].t, 101.0, 1e-6);
    EXPECT_THROW(hymm::datasets::pairScansByRanges(dir.file("a.rawlog"), c, 0.0), std::invalid_argument);
    EXPECT_THROW(hymm::datasets::pairScansByRanges(dir.file("none.rawlog"), c), std::runtime_error);
}

}  // namespace
