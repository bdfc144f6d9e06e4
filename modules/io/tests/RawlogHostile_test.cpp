// Mutated copies of the bundled chapter-3 rawlog: declared sizes that do not fit in the
// file must end in a clear error naming the file and entry, within bounded memory.
#include "rawlog_hostile_support.h"

#include <gtest/gtest.h>
#include <hymm/io/RawlogReader.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/poses/CPosePDFParticles.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace
{
using namespace hymm_hostile;

// Offset of the beam count of the n-th 2D scan (MRPT 2.5, version 7): version byte,
// aperture, rightToLeft, maxRange, then a CPose3D object (v3: 12 doubles) and its end flag.
size_t scanBeamCountOffset(const std::vector<uint8_t>& d, size_t nth)
{
    const size_t at = afterClassName(d, "CObservation2DRangeScan", nth);
    EXPECT_EQ(d[at], 7) << "2D scan version";
    const size_t pose = at + 1 + 9;
    EXPECT_EQ(d[pose], 0x80 | 20) << "mrpt::poses::CPose3D";
    EXPECT_EQ(d[pose + 21], 3) << "CPose3D version";
    return pose + 22 + 96 + 1;
}

TEST(RawlogHostileTest, SampleReadsCleanlyThroughTheGuard)
{
    const auto data = gunzip(kSample);
    const auto path = writeGz(data);
    const auto r = readInChild(path, budgetFor(data));
    ASSERT_TRUE(r.exited);
    EXPECT_EQ(r.code, 1) << r.message;
    hymm::io::RawlogReader reader(kSample);
    hymm::io::RawlogEntry e;
    size_t scans = 0;
    while (reader.next(e))
        if (e.frame) scans += e.frame->size();
    EXPECT_GT(scans, 400u);
}

TEST(RawlogHostileTest, HugeBeamCountIsRefusedBeforeAllocation)
{
    auto data = gunzip(kSample);
    const size_t at = scanBeamCountOffset(data, 3);
    ASSERT_GT(getU32(data, at), 0u);
    ASSERT_LT(getU32(data, at), 100000u) << "not a beam count";
    putU32(data, at, 0x10000000);
    const auto path = writeGz(data);
    expectCleanError(path, data, "entry ", "declares 268435456 beams");
}

TEST(RawlogHostileTest, BeamCountJustBeyondTheFileIsRefused)
{
    // Every other value fits; the count is as large as the rest of the file allows + 1.
    auto data = gunzip(kSample);
    const size_t at = scanBeamCountOffset(data, 0);
    const auto left = static_cast<uint32_t>(data.size() - at - 4);
    putU32(data, at, left / 5 + 1);
    const auto path = writeGz(data);
    expectCleanError(path, data, "entry 1", "beams");
}

TEST(RawlogHostileTest, HugeSensorLabelLengthIsRefused)
{
    auto data = gunzip(kSample);
    const size_t at = scanBeamCountOffset(data, 5);
    const uint32_t n = getU32(data, at);
    const size_t label = at + 4 + 5 * size_t{n} + 16;
    ASSERT_LT(getU32(data, label), 1000u) << "not a label length";
    putU32(data, label, 0xF0000000u);
    const auto path = writeGz(data);
    expectCleanError(path, data, "entry ", "bytes of sensor label");
}

TEST(RawlogHostileTest, HugeObservationCountOfAFrameIsRefused)
{
    auto data = gunzip(kSample);
    const size_t at = afterClassName(data, "CSensoryFrame", 2);
    ASSERT_EQ(data[at], 2) << "CSensoryFrame version";
    ASSERT_EQ(getU32(data, at + 1), 2u) << "observations in the frame";
    putU32(data, at + 1, 0x20000000);
    const auto path = writeGz(data);
    expectCleanError(path, data, "entry 5", "declares 536870912 observations");
}

TEST(RawlogHostileTest, HugeMeasurementCountIsRefused)
{
    auto data = gunzip(kSample);
    const size_t at = afterClassName(data, "CObservationBearingRange", 4);
    ASSERT_EQ(data[at], 3) << "CObservationBearingRange version";
    // v3 layout: 4 floats, CPose3D (v3), timestamp, validCovariances (+3 floats if false).
    const size_t pose = at + 1 + 16;
    ASSERT_EQ(data[pose], 0x80 | 20);
    size_t cnt = pose + 22 + 96 + 1 + 8;
    cnt += 1 + (data[cnt] ? 0 : 12);
    ASSERT_LT(getU32(data, cnt), 10000u) << "not a measurement count";
    putU32(data, cnt, 0x7FFFFFFF);
    const auto path = writeGz(data);
    expectCleanError(path, data, "entry ", "measurements");
}

TEST(RawlogHostileTest, CorruptGzipDataIsReportedAsCorrupt)
{
    std::ifstream in(kSample, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 1000u);
    for (size_t i = bytes.size() / 2; i < bytes.size() / 2 + 64; ++i) bytes[i] = static_cast<char>(~bytes[i]);
    const std::string path = mrpt::system::getTempFileName() + ".rawlog";
    std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    try
    {
        hymm::io::RawlogReader r(path);
        hymm::io::RawlogEntry e;
        while (r.next(e))
        {
        }
        FAIL() << "corrupt gzip data read without an error";
    }
    catch (const std::runtime_error& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("corrupt"), std::string::npos) << m;
        EXPECT_NE(m.find("gzip"), std::string::npos) << m;
        EXPECT_NE(m.find("entry"), std::string::npos) << m;
        EXPECT_NE(m.find(path), std::string::npos) << m;
    }
}

TEST(RawlogHostileTest, GzipCutShortIsReportedAsTruncated)
{
    std::ifstream in(kSample, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    bytes.resize(bytes.size() * 2 / 3);
    const std::string path = mrpt::system::getTempFileName() + ".rawlog";
    std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    hymm::io::RawlogReader r(path);
    hymm::io::RawlogEntry e;
    try
    {
        while (r.next(e))
        {
        }
        FAIL() << "a cut gzip file read as complete";
    }
    catch (const std::runtime_error& ex)
    {
        EXPECT_NE(std::string(ex.what()).find("truncated"), std::string::npos) << ex.what();
        EXPECT_GT(r.entriesRead(), 100u);
    }
}

// A small rawlog of hand-made objects holding the other counts and strings the guard
// checks: an odometry observation, bearing-range observations with and without
// per-measurement covariance matrices, a Thrun motion model and a particle PDF.
std::vector<uint8_t> handMadeRawlog()
{
    using namespace mrpt::obs;
    std::vector<mrpt::serialization::CSerializable::Ptr> objs;
    {
        auto sf = CSensoryFrame::Create();
        auto odo = CObservationOdometry::Create();
        odo->sensorLabel = "ODOLABEL";
        odo->odometry = mrpt::poses::CPose2D(1, 2, 0.3);
        sf->insert(odo);
        auto br = CObservationBearingRange::Create();
        br->sensorLabel = "BRLABEL1";
        br->validCovariances = false;
        br->sensedData.resize(3);
        for (int i = 0; i < 3; ++i) br->sensedData[i].landmarkID = i;
        sf->insert(br);
        objs.push_back(sf);
    }
    {
        auto br = CObservationBearingRange::Create();
        br->sensorLabel = "BRLABEL2";
        br->validCovariances = true;
        br->sensedData.resize(4);
        for (int i = 0; i < 4; ++i)
        {
            br->sensedData[i].landmarkID = 10 + i;
            br->sensedData[i].covariance.setIdentity();
        }
        objs.push_back(br);
    }
    {
        auto acts = CActionCollection::Create();
        CActionRobotMovement2D thrun;
        CActionRobotMovement2D::TMotionModelOptions opts;
        opts.modelSelection = CActionRobotMovement2D::mmThrun;
        opts.thrunModel.nParticlesCount = 4321;
        thrun.computeFromOdometry(mrpt::poses::CPose2D(0.5, 0, 0.1), opts);
        acts->insert(thrun);
        CActionRobotMovement2D particles;
        particles.estimationMethod = CActionRobotMovement2D::emScan2DMatching;
        particles.poseChange = mrpt::poses::CPosePDFParticles::Create(5);
        acts->insert(particles);
        objs.push_back(acts);
    }
    mrpt::io::CMemoryStream mem;
    auto arch = mrpt::serialization::archiveFrom(mem);
    for (const auto& o : objs) arch << *o;
    const auto* p = static_cast<const uint8_t*>(mem.getRawBufferData());
    return {p, p + mem.getTotalBytesCount()};
}

size_t find(const std::vector<uint8_t>& d, const std::vector<uint8_t>& pat, size_t from = 0)
{
    const auto it = std::search(d.begin() + static_cast<std::ptrdiff_t>(from), d.end(), pat.begin(), pat.end());
    if (it == d.end()) throw std::runtime_error("pattern not found");
    return static_cast<size_t>(it - d.begin());
}

// Offset of the length of a serialised string `s` (uint32 length, then the bytes).
size_t stringLengthAt(const std::vector<uint8_t>& d, const std::string& s)
{
    std::vector<uint8_t> pat(4);
    const auto n = static_cast<uint32_t>(s.size());
    std::memcpy(pat.data(), &n, 4);
    pat.insert(pat.end(), s.begin(), s.end());
    return find(d, pat);
}

size_t afterName(const std::vector<uint8_t>& d, const std::string& qualified, size_t from = 0)
{
    std::vector<uint8_t> pat{static_cast<uint8_t>(0x80 | qualified.size())};
    pat.insert(pat.end(), qualified.begin(), qualified.end());
    return find(d, pat, from) + pat.size();
}

void expectHandMadeRefused(std::vector<uint8_t> data, size_t at, uint32_t value,
                           const std::string& what)
{
    putU32(data, at, value);
    const auto path = writeGz(data);
    expectCleanError(path, data, "entry ", what);
}

TEST(RawlogHostileTest, HandMadeRawlogReadsCleanlyThroughTheGuard)
{
    const auto data = handMadeRawlog();
    const auto path = writeGz(data);
    hymm::io::RawlogReader r(path);
    hymm::io::RawlogEntry e;
    ASSERT_TRUE(r.next(e));
    ASSERT_TRUE(e.frame);
    EXPECT_EQ(e.frame->size(), 2u);
    ASSERT_TRUE(r.next(e));
    auto br = std::dynamic_pointer_cast<mrpt::obs::CObservationBearingRange>(e.observation);
    ASSERT_TRUE(br);
    EXPECT_EQ(br->sensorLabel, "BRLABEL2");
    EXPECT_EQ(br->sensedData.size(), 4u);
    ASSERT_TRUE(r.next(e));
    ASSERT_TRUE(e.actions);
    EXPECT_EQ(e.actions->size(), 2u);
    EXPECT_FALSE(r.next(e));
}

TEST(RawlogHostileTest, HugeBearingRangeLabelIsRefused)
{
    // The fuzz finding: a label declaring 2.6 GB.
    const auto data = handMadeRawlog();
    expectHandMadeRefused(data, stringLengthAt(data, "BRLABEL1"), 0x9C000000u,
                          "bytes of sensor label");
}

TEST(RawlogHostileTest, HugeLabelAfterCovarianceMatricesIsRefused)
{
    const auto data = handMadeRawlog();
    expectHandMadeRefused(data, stringLengthAt(data, "BRLABEL2"), 0x7FFFFFFFu,
                          "bytes of sensor label");
}

TEST(RawlogHostileTest, HugeMeasurementCountWithCovariancesIsRefused)
{
    auto data = handMadeRawlog();
    // The count sits right before the first measurement's range, yaw, pitch and ID 10.
    const size_t first_cov = afterName(data, "mrpt::math::CMatrixD");
    const size_t cnt = first_cov - 21 - 16 - 4;
    ASSERT_EQ(getU32(data, cnt), 4u);
    expectHandMadeRefused(data, cnt, 0x10000000u, "measurements");
}

TEST(RawlogHostileTest, HugeMeasurementCountBehindAFlippedCovarianceFlagIsRefused)
{
    // The fuzz finding: validCovariances set in an observation written without matrices,
    // so the bytes after each measurement are no matrix object; the count (read where the
    // three sensor std floats were) must still be refused before MRPT sizes the vector
    // (128 B per measurement: 32 GiB here).
    auto data = handMadeRawlog();
    const size_t at = afterName(data, "mrpt::obs::CObservationBearingRange");
    ASSERT_EQ(data[at], 3) << "CObservationBearingRange version";
    const size_t pose = at + 1 + 16;
    ASSERT_EQ(data[pose], 0x80 | 20) << "mrpt::poses::CPose3D";
    const size_t valid = pose + 22 + 96 + 1 + 8;
    ASSERT_EQ(data[valid], 0) << "validCovariances";
    ASSERT_EQ(getU32(data, valid + 1 + 12), 3u) << "measurement count";
    data[valid] = 1;
    expectHandMadeRefused(data, valid + 1, 0x10000000u, "declares 268435456 measurements");
}

TEST(RawlogHostileTest, HugeCovarianceMatrixIsRefused)
{
    const auto data = handMadeRawlog();
    const size_t rows = afterName(data, "mrpt::math::CMatrixD") + 1;
    ASSERT_EQ(getU32(data, rows), 3u);
    expectHandMadeRefused(data, rows, 0x40000000u, "matrix elements");
}

TEST(RawlogHostileTest, HugeOdometryLabelIsRefused)
{
    const auto data = handMadeRawlog();
    expectHandMadeRefused(data, stringLengthAt(data, "ODOLABEL"), 0xF0000000u,
                          "bytes of sensor label");
}

TEST(RawlogHostileTest, HugeMotionModelSampleCountIsRefused)
{
    const auto data = handMadeRawlog();
    const size_t from = afterName(data, "mrpt::obs::CActionRobotMovement2D");
    std::vector<uint8_t> pat(4);
    const uint32_t n = 4321;
    std::memcpy(pat.data(), &n, 4);
    expectHandMadeRefused(data, find(data, pat, from), 0xFFFFFFF0u, "motion-model particles");
}

TEST(RawlogHostileTest, HugeParticleCountIsRefused)
{
    const auto data = handMadeRawlog();
    const size_t at = afterName(data, "mrpt::poses::CPosePDFParticles");
    ASSERT_EQ(data[at], 1) << "CPosePDFParticles version";
    ASSERT_EQ(getU32(data, at + 1), 5u);
    expectHandMadeRefused(data, at + 1, 0x7FFFFFFFu, "particles");
}

TEST(RawlogHostileTest, NestedCollectionsCannotEachClaimTheRestOfTheFile)
{
    // A frame declaring as many observations as the rest of the file could hold, whose
    // first observation declares as many beacon measurements as the same bytes could
    // hold: MRPT sizes both containers before reading their first elements, so each
    // level's claim must leave the bytes the enclosing levels' remaining elements need.
    // (Frames nested in frames, which once let memory grow with the file size times the
    // depth, are refused outright now: a frame's element must be an observation.)
    const std::string frame = "mrpt::obs::CSensoryFrame";
    const std::string beacons = "mrpt::obs::CObservationBeaconRanges";
    constexpr size_t kPadding = 200000;
    std::vector<uint8_t> data;
    const auto header = [&](const std::string& name, uint8_t version)
    {
        data.push_back(static_cast<uint8_t>(0x80 | name.size()));
        data.insert(data.end(), name.begin(), name.end());
        data.push_back(version);
    };
    header(frame, 2);
    const size_t frame_count = data.size();
    data.resize(data.size() + 4);
    header(beacons, 3);
    data.resize(data.size() + 12);  // three floats
    const size_t beacon_count = data.size();
    data.resize(data.size() + 4 + kPadding, 0);
    // Each alone fits: 9 bytes per observation, 17 per measurement (and the tail).
    putU32(data, frame_count, static_cast<uint32_t>((data.size() - frame_count - 4) / 9));
    putU32(data, beacon_count, static_cast<uint32_t>((kPadding - 64) / 17));
    const auto path = writeGz(data);
    expectCleanError(path, data, "entry 0", "needed by the enclosing objects' remaining elements");
}

// The file ends inside an action collection's 4-byte count: three of its bytes are
// there. MRPT's ReadBuffer accepts the short read and the count's fourth byte keeps
// whatever it held, so MRPT sized a container of at least 13 million actions (2.1 GB
// found by rawlog_fuzz: regressions/rawlog/oom_count_cut_by_end_of_file). The guard
// refuses a read the data cannot fill, and the entry is reported as truncated.
TEST(RawlogHostileTest, CountCutByTheEndOfTheFileIsATruncatedEntry)
{
    const std::string name = "mrpt::obs::CActionCollection";
    std::vector<uint8_t> data;
    data.push_back(static_cast<uint8_t>(0x80 | name.size()));
    data.insert(data.end(), name.begin(), name.end());
    data.push_back(0);  // version
    data.insert(data.end(), {0x01, 0x00, 0xc8});  // three of the count's four bytes
    const auto path = writeGz(data);
    expectCleanError(path, data, "entry 0", "is truncated in entry 0");
}

TEST(RawlogHostileTest, ZeroByteInAClassNameDoesNotHideTheCounts)
{
    // MRPT reads the class name into a C string: "mrpt::obs::CActionCollection\0xyz" is a
    // CActionCollection, whose action count must be checked like any other.
    const std::string name = std::string("mrpt::obs::CActionCollection") + '\0' + "xyz";
    std::vector<uint8_t> data(1 + name.size() + 1 + 4 + 64, 0);
    data[0] = static_cast<uint8_t>(0x80 | name.size());
    std::memcpy(&data[1], name.data(), name.size());
    data[1 + name.size()] = 0;  // version 0
    putU32(data, 2 + name.size(), 0x7FFFFFFFu);
    const auto path = writeGz(data);
    expectCleanError(path, data, "entry 0", "declares 2147483647 actions");
}

TEST(RawlogHostileTest, NullPosePdfOfAMovementIsRefused)
{
    // A movement estimated by other means than odometry carries its pose PDF; MRPT copies
    // the PDF it reads through the pointer without a null check, so a serialised null
    // object there was a segmentation fault inside MRPT (found by the rawlog fuzz target).
    using namespace mrpt::obs;
    const auto serialise = [](const mrpt::serialization::CSerializable& o) {
        mrpt::io::CMemoryStream mem;
        auto arch = mrpt::serialization::archiveFrom(mem);
        arch << o;
        const auto* p = static_cast<const uint8_t*>(mem.getRawBufferData());
        return std::vector<uint8_t>(p, p + mem.getTotalBytesCount());
    };
    const mrpt::poses::CPosePDFGaussian pdf(mrpt::poses::CPose2D(0.5, 0, 0.1));
    CActionCollection acts;
    CActionRobotMovement2D mov;
    mov.estimationMethod = CActionRobotMovement2D::emScan2DMatching;
    mov.poseChange = mrpt::poses::CPosePDFGaussian::Create(pdf);
    acts.insert(mov);
    const auto whole = serialise(acts);
    const auto pdf_bytes = serialise(pdf);
    const auto at = std::search(whole.begin(), whole.end(), pdf_bytes.begin(), pdf_bytes.end());
    ASSERT_NE(at, whole.end()) << "the PDF's bytes inside the action";
    // The same object with the PDF replaced by a null one (0x80 | 7, "nullptr", end flag).
    std::vector<uint8_t> data(whole.begin(), at);
    const std::string null_name = "nullptr";
    data.push_back(0x80 | 7);
    data.insert(data.end(), null_name.begin(), null_name.end());
    data.push_back(0x88);
    data.insert(data.end(), at + static_cast<std::ptrdiff_t>(pdf_bytes.size()), whole.end());
    {
        // Unchanged, the file reads.
        const auto path = writeGz(whole);
        const auto r = readInChild(path, budgetFor(whole));
        ASSERT_TRUE(r.exited);
        EXPECT_EQ(r.code, 1) << r.message;
    }
    const auto path = writeGz(data);
    expectCleanError(path, data, "entry 0", "holds a null object where a CActionRobotMovement2D's pose PDF belongs");
}


// A beacon-range observation is not read by the pipeline, but MRPT deserialises it inside
// a sensory frame and sized its measurements from the count alone (found by the long
// rawlog_fuzz run: 47 million measurements, 23 GB in the Release replay).
TEST(RawlogHostileTest, HugeBeaconRangeCountIsRefused)
{
    using namespace mrpt::obs;
    CObservationBeaconRanges obs;
    obs.sensorLabel = "beacons";
    for (int i = 0; i < 3; ++i)
    {
        CObservationBeaconRanges::TMeasurement m;
        m.sensedDistance = 2.0f + static_cast<float>(i);
        m.beaconID = i;
        obs.sensedData.push_back(m);
    }
    CSensoryFrame sf;
    sf.insert(CObservationBeaconRanges::Create(obs));
    auto data = serialised(sf);
    {
        const auto path = writeGz(data);
        const auto r = readInChild(path, budgetFor(data));
        ASSERT_TRUE(r.exited);
        EXPECT_EQ(r.code, 1) << r.message;  // unchanged, it reads
    }
    // The count follows the class name, the version byte and three floats.
    const std::string name = "mrpt::obs::CObservationBeaconRanges";
    const auto at = std::search(data.begin(), data.end(), name.begin(), name.end());
    ASSERT_NE(at, data.end());
    const size_t count = static_cast<size_t>(at - data.begin()) + name.size() + 1 + 12;
    ASSERT_EQ(getU32(data, count), 3u);
    putU32(data, count, 0x7FFFFFFFu);
    const auto path = writeGz(data);
    expectCleanError(path, data, "entry 0", "beacon measurements");
}

// A class name that MRPT knows but cannot create (an abstract base: CPosePDF, CAction,
// CObservation): MRPT warns and reads an empty pointer in its place, then dereferences it
// (found by the long rawlog_fuzz run: a movement's pose PDF named
// mrpt::poses::CPosePDF, SEGV in CActionRobotMovement2D::serializeFrom;
// regressions/rawlog/segv_abstract_pose_pdf_class). Refused wherever it appears.
TEST(RawlogHostileTest, AbstractClassNamesAreRefused)
{
    using namespace mrpt::obs;
    const auto renamed = [](const std::vector<uint8_t>& whole, const std::vector<uint8_t>& part,
                            const std::string& name) {
        const auto at = std::search(whole.begin(), whole.end(), part.begin(), part.end());
        EXPECT_NE(at, whole.end());
        EXPECT_TRUE(part[0] & 0x80);
        if (at == whole.end()) return std::vector<uint8_t>{};
        const size_t old_len = part[0] & 0x7F;
        std::vector<uint8_t> data(whole.begin(), at);
        data.push_back(static_cast<uint8_t>(0x80 | name.size()));
        data.insert(data.end(), name.begin(), name.end());
        data.insert(data.end(), at + 1 + static_cast<std::ptrdiff_t>(old_len), whole.end());
        return data;
    };
    const mrpt::poses::CPosePDFGaussian pdf(mrpt::poses::CPose2D(0.5, 0, 0.1));
    CActionRobotMovement2D mov;
    mov.estimationMethod = CActionRobotMovement2D::emScan2DMatching;
    mov.poseChange = mrpt::poses::CPosePDFGaussian::Create(pdf);
    CActionCollection acts;
    acts.insert(mov);
    const auto whole = serialised(acts);
    {
        const auto path = writeGz(whole);
        const auto r = readInChild(path, budgetFor(whole));
        ASSERT_TRUE(r.exited);
        EXPECT_EQ(r.code, 1) << r.message;  // unchanged, it reads
    }
    // The movement's pose PDF, then the movement itself, named by their abstract bases.
    for (const auto& [part, name] :
         {std::pair{serialised(pdf), std::string("mrpt::poses::CPosePDF")},
          std::pair{serialised(mov), std::string("mrpt::obs::CAction")}})
    {
        SCOPED_TRACE(name);
        const auto data = renamed(whole, part, name);
        const auto path = writeGz(data);
        expectCleanError(path, data, "entry 0",
                         "names the abstract class '" + name.substr(name.rfind(':') + 1) + "'");
    }
}

// A CActionCollection as MRPT writes it (header, version 0, count, elements, end flag)
// holding the given serialised objects, whatever their class.
std::vector<uint8_t> collectionOf(const std::vector<std::vector<uint8_t>>& elements)
{
    auto data = serialised(mrpt::obs::CActionCollection());  // header, count 0, end flag
    data.resize(data.size() - 5);
    const auto n = static_cast<uint32_t>(elements.size());
    const auto* nb = reinterpret_cast<const uint8_t*>(&n);
    data.insert(data.end(), nb, nb + 4);
    for (const auto& e : elements) data.insert(data.end(), e.begin(), e.end());
    data.push_back(0x88);
    return data;
}

std::vector<uint8_t> concat(const std::vector<std::vector<uint8_t>>& parts)
{
    std::vector<uint8_t> out;
    for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
    return out;
}

TEST(RawlogHostileTest, ActionCollectionElementsMustBeActions)
{
    // MRPT reads each element of an action collection into a deep-copying pointer that
    // clones it without a null check: an element that is a null object, or an object of
    // another class (the cast to CAction gives null), was a segmentation fault inside
    // MRPT (found by the rawlog fuzz target, a CActionCollection among the actions).
    using namespace mrpt::obs;
    // Actions with nested objects, velocities and encoders, so that the reader must
    // follow where each one ends: a particle PDF larger than the guard's look-ahead, a
    // Gaussian one, raw odometry, and a 3-D movement.
    CActionRobotMovement2D particles;
    particles.estimationMethod = CActionRobotMovement2D::emScan2DMatching;
    auto pdf = mrpt::poses::CPosePDFParticles::Create(500);
    for (size_t i = 0; i < pdf->size(); ++i) pdf->m_particles[i].d = mrpt::math::TPose2D(0.01 * i, 0, 0);
    particles.poseChange = pdf;
    particles.hasVelocities = true;
    particles.velocityLocal = mrpt::math::TTwist2D(0.5, 0, 0.1);
    CActionRobotMovement2D gaussian;
    gaussian.estimationMethod = CActionRobotMovement2D::emScan2DMatching;
    gaussian.poseChange = mrpt::poses::CPosePDFGaussian::Create(mrpt::poses::CPose2D(0.5, 0, 0.1));
    gaussian.hasEncodersInfo = true;
    gaussian.encoderLeftTicks = 120;
    gaussian.encoderRightTicks = 136;
    CActionRobotMovement2D odometry;
    odometry.computeFromOdometry(mrpt::poses::CPose2D(0.3, 0.01, 0.02), CActionRobotMovement2D::TMotionModelOptions());
    CActionRobotMovement3D mov3d;
    mov3d.poseChange = mrpt::poses::CPose3DPDFGaussian(mrpt::poses::CPose3D(0.2, 0, 0, 0.1, 0, 0));
    mov3d.hasVelocities = {true, false, false, false, false, true};
    const auto a = serialised(particles), b = serialised(gaussian), c = serialised(odometry), d = serialised(mov3d);
    // The Gaussian action as an older MRPT wrote it: a version-0 PDF whose covariance is a
    // CMatrixF object named without its namespace, so its header starts with the byte
    // 0x88 (0x80 | 8 characters), as an end flag does.
    const auto gaussian_pdf = serialised(mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(0.5, 0, 0.1)));
    std::vector<uint8_t> old_pdf;
    {
        const std::string pdf_name = "mrpt::poses::CPosePDFGaussian";
        old_pdf.push_back(static_cast<uint8_t>(0x80 | pdf_name.size()));
        old_pdf.insert(old_pdf.end(), pdf_name.begin(), pdf_name.end());
        old_pdf.push_back(0);  // version 0: mean, then the covariance as a CMatrixF object
        const auto mean = serialised(mrpt::poses::CPose2D(0.5, 0, 0.1));
        old_pdf.insert(old_pdf.end(), mean.begin(), mean.end());
        const std::string m_name = "CMatrixF";
        old_pdf.push_back(static_cast<uint8_t>(0x80 | m_name.size()));
        old_pdf.insert(old_pdf.end(), m_name.begin(), m_name.end());
        old_pdf.push_back(0);  // CMatrixF version 0: rows, columns, floats
        const uint32_t three = 3;
        for (int k = 0; k < 2; ++k)
            old_pdf.insert(old_pdf.end(), reinterpret_cast<const uint8_t*>(&three),
                           reinterpret_cast<const uint8_t*>(&three) + 4);
        for (int k = 0; k < 9; ++k)
        {
            const float x = k % 4 == 0 ? 0.01f : 0.0f;
            old_pdf.insert(old_pdf.end(), reinterpret_cast<const uint8_t*>(&x),
                           reinterpret_cast<const uint8_t*>(&x) + 4);
        }
        old_pdf.push_back(0x88);  // the matrix's end flag
        old_pdf.push_back(0x88);  // the PDF's end flag
    }
    std::vector<uint8_t> b_old;
    {
        const auto at = std::search(b.begin(), b.end(), gaussian_pdf.begin(), gaussian_pdf.end());
        ASSERT_NE(at, b.end()) << "the PDF's bytes inside the action";
        b_old.assign(b.begin(), at);
        b_old.insert(b_old.end(), old_pdf.begin(), old_pdf.end());
        b_old.insert(b_old.end(), at + static_cast<std::ptrdiff_t>(gaussian_pdf.size()), b.end());
    }
    CSensoryFrame frame;
    auto odo = CObservationOdometry::Create();
    odo->odometry = mrpt::poses::CPose2D(1, 2, 0.3);
    frame.insert(odo);
    const auto f = serialised(frame);
    const auto pose = serialised(mrpt::poses::CPose2D(1, 2, 3));
    const std::vector<uint8_t> null_object = {0x80 | 7, 'n', 'u', 'l', 'l', 'p', 't', 'r', 0x88};
    {
        // Well formed: collections of every kind of action, frames between them (a frame
        // after a collection is no action of it), a collection that is not the first entry.
        const auto data = concat({collectionOf({a, b, c, d}), f, collectionOf({d, c}), f,
                                  collectionOf({}), collectionOf({b}), collectionOf({b_old, c})});
        const auto path = writeGz(data);
        const auto r = readInChild(path, budgetFor(data));
        ASSERT_TRUE(r.exited) << "killed by signal " << r.signal;
        EXPECT_EQ(r.code, 1) << r.message;
    }
    struct Case
    {
        std::vector<uint8_t> data;
        std::string entry, what;
    };
    // The hasVelocities byte of the first action (just after its PDF) set to 0x88, as an
    // end flag is: it must not end the action early and let the next element through.
    auto a_flag = a;
    const auto pdf_bytes = serialised(*pdf);
    const auto at = std::search(a_flag.begin(), a_flag.end(), pdf_bytes.begin(), pdf_bytes.end());
    ASSERT_NE(at, a_flag.end());
    *(at + static_cast<std::ptrdiff_t>(pdf_bytes.size())) = 0x88;
    const std::vector<Case> cases = {
        {collectionOf({b, pose}), "entry 0", "holds a 'CPose2D' where an action of a CActionCollection belongs"},
        {collectionOf({a, null_object, c}), "entry 0", "holds a null object where an action of a CActionCollection belongs"},
        {concat({f, collectionOf({f})}), "entry 1", "holds a 'CSensoryFrame' where an action"},
        {collectionOf({d, collectionOf({b})}), "entry 0", "holds a 'CActionCollection' where an action"},
        {collectionOf({a_flag, pose}), "entry 0", "holds a 'CPose2D' where an action"},
        // The matrix's length byte 0x88 must not end the PDF early (the PDF's own end flag
        // would then end the action, the action's the collection, and the pose get in).
        {collectionOf({b_old, pose}), "entry 0", "holds a 'CPose2D' where an action"},
        {concat({collectionOf({b}), f, collectionOf({c, d, null_object})}), "entry 2", "holds a null object where an action"},
    };
    for (const auto& k : cases)
    {
        SCOPED_TRACE(k.what + " (" + k.entry + ")");
        const auto path = writeGz(k.data);
        expectCleanError(path, k.data, k.entry, k.what);
    }
}

TEST(RawlogHostileTest, HugeCountsOfA3DMovementAreRefused)
{
    // A 3-D movement's velocity flags and velocities are counted vectors MRPT sizes
    // before reading them (a flag costs a byte and a bit, a velocity 4 bytes).
    mrpt::obs::CActionRobotMovement3D mov;
    mov.poseChange = mrpt::poses::CPose3DPDFGaussian(mrpt::poses::CPose3D(0.2, 0, 0, 0.1, 0, 0));
    mov.hasVelocities = {true, false, false, false, false, true};
    const auto data = collectionOf({serialised(mov), serialised(mov)});
    {
        const auto path = writeGz(data);
        const auto r = readInChild(path, budgetFor(data));
        ASSERT_TRUE(r.exited) << "killed by signal " << r.signal;
        EXPECT_EQ(r.code, 1) << r.message;
    }
    // The flags' count: 6, then the six bytes 1 0 0 0 0 1, then the velocities' count 6.
    const std::vector<uint8_t> pat = {6, 0, 0, 0, 1, 0, 0, 0, 0, 1, 6, 0, 0, 0};
    const size_t flags = find(data, pat, afterName(data, "mrpt::obs::CActionRobotMovement3D"));
    expectHandMadeRefused(data, flags, 0xF0000000u, "velocity flags");
    expectHandMadeRefused(data, flags + 10, 0x40000000u, "velocities");
    const size_t second = find(data, pat, flags + pat.size());
    expectHandMadeRefused(data, second + 10, 0x40000000u, "velocities");
}

}  // namespace
