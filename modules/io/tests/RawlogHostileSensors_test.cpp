// Observation classes HYMM does not read but MRPT builds inside sensory frames (to count
// them by class name): their declared sizes must not make MRPT allocate beyond the file.
// Each case writes one valid observation, checks it reads, then mutates one size.
#include "rawlog_hostile_support.h"

// jpeglib.h needs FILE and size_t declared first.
#include <cstddef>
#include <cstdio>
#include <jpeglib.h>

#include <gtest/gtest.h>
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservationBatteryState.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/gnss_messages_novatel.h>
#include <mrpt/obs/gnss_messages_topcon.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservation6DFeatures.h>
#include <mrpt/obs/CObservationCANBusJ1939.h>
#include <mrpt/obs/CObservationGasSensors.h>
#include <mrpt/obs/CObservationRFID.h>
#include <mrpt/obs/CObservationRGBD360.h>
#include <mrpt/obs/CObservationRawDAQ.h>
#include <mrpt/obs/CObservationRange.h>
#include <mrpt/obs/CObservationReflectivity.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CObservationSkeleton.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CObservationStereoImagesFeatures.h>
#include <mrpt/obs/CObservationWindSensor.h>
#include <mrpt/obs/CObservationWirelessPower.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace
{
using namespace hymm_hostile;

template <class Obs>
std::vector<uint8_t> inFrame(const Obs& obs)
{
    mrpt::obs::CSensoryFrame sf;
    sf.insert(Obs::Create(obs));
    return serialised(sf);
}

void expectReads(const std::vector<uint8_t>& data)
{
    const auto r = readInChild(writeGz(data), budgetFor(data));
    ASSERT_TRUE(r.exited) << "killed by signal " << r.signal;
    EXPECT_EQ(r.code, 1) << r.message;
}

size_t find(const std::vector<uint8_t>& d, const std::string& s, size_t from = 0)
{
    const auto it = std::search(d.begin() + static_cast<std::ptrdiff_t>(from), d.end(), s.begin(), s.end(),
                                [](uint8_t a, char b) { return a == static_cast<uint8_t>(b); });
    if (it == d.end()) throw std::runtime_error("'" + s + "' not in the data");
    return static_cast<size_t>(it - d.begin());
}

// The offset of the length of the (only) string `text` in the data, checked.
size_t lengthOf(const std::vector<uint8_t>& d, const std::string& text)
{
    const size_t at = find(d, text) - 4;
    EXPECT_EQ(getU32(d, at), text.size()) << "not the length of '" << text << "'";
    return at;
}

void expectRefused(std::vector<uint8_t> data, size_t at, uint32_t value, const std::string& what)
{
    putU32(data, at, value);
    expectCleanError(writeGz(data), data, "entry 0", what);
}

template <class Obs>
void expectLabelGuarded(Obs obs, const std::string& label)
{
    obs.sensorLabel = label;
    const auto data = inFrame(obs);
    expectReads(data);
    expectRefused(data, lengthOf(data, label), 0xF0000000u, "bytes of sensor label");
}

TEST(RawlogHostileSensorsTest, HugeCommentLengthIsRefused)
{
    mrpt::obs::CObservationComment obs;
    obs.text = "a comment in a frame";
    const auto data = inFrame(obs);
    expectReads(data);
    expectRefused(data, lengthOf(data, obs.text), 0x7FFFFFF0u, "bytes of comment text");
}

TEST(RawlogHostileSensorsTest, HugeRangeCountAndLabelAreRefused)
{
    mrpt::obs::CObservationRange obs;
    obs.sensorLabel = "sonar_ring";
    for (uint16_t i = 0; i < 3; ++i)
    {
        mrpt::obs::CObservationRange::TMeasurement m;
        m.sensorID = i;
        m.sensorPose = mrpt::math::TPose3D(0.1 * i, 0, 0.2, 0.5 * i, 0, 0);
        m.sensedDistance = 1.5f;
        obs.sensedData.push_back(m);
    }
    const auto data = inFrame(obs);
    expectReads(data);
    // The count follows the class name, the version byte and three floats.
    const size_t count = find(data, "mrpt::obs::CObservationRange") + 28 + 1 + 12;
    ASSERT_EQ(getU32(data, count), 3u);
    expectRefused(data, count, 0x7FFFFFFFu, "range measurements");
    expectRefused(data, lengthOf(data, obs.sensorLabel), 0xF0000000u, "bytes of sensor label");
}

TEST(RawlogHostileSensorsTest, HugeImuLabelIsRefused)
{
    mrpt::obs::CObservationIMU obs;
    obs.set(mrpt::obs::IMU_WZ, 0.25);
    expectLabelGuarded(obs, "xsens_imu");
}

TEST(RawlogHostileSensorsTest, HugeGpsLabelIsRefused)
{
    mrpt::obs::CObservationGPS obs;
    mrpt::obs::gnss::Message_NMEA_GGA gga;
    gga.fields.latitude_degrees = 36.7;
    gga.fields.fix_quality = 1;
    obs.setMsg(gga);
    expectLabelGuarded(obs, "gnss_receiver");
}

mrpt::obs::CObservationImage imageObservation(const mrpt::img::CImage& img)
{
    mrpt::obs::CObservationImage obs;
    obs.sensorLabel = "camera";
    obs.image = img;
    return obs;
}

mrpt::img::CImage pattern(int w, int h, mrpt::img::TImageChannels ch)
{
    mrpt::img::CImage img(w, h, ch);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < static_cast<int>(ch); ++c) *img(x, y, c) = static_cast<uint8_t>(x * 7 + y * 3 + c);
    return img;
}

// Offset of a serialised CImage's first data byte (past its class name and version).
size_t imageData(const std::vector<uint8_t>& d)
{
    const size_t at = find(d, "mrpt::img::CImage") + 17;
    EXPECT_EQ(d[at], 9) << "CImage version";
    return at + 1;
}

// An image observation in a frame, its colour image written as a JPEG or raw (MRPT 2.5
// writes colour images raw unless told otherwise; images are serialised with the frame).
std::vector<uint8_t> imageFrame(const mrpt::obs::CObservationImage& obs, bool jpeg)
{
    const bool raw = mrpt::img::CImage::DISABLE_JPEG_COMPRESSION();
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(!jpeg);
    auto data = inFrame(obs);
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(raw);
    return data;
}

TEST(RawlogHostileSensorsTest, HugeGreyImageIsRefusedBeforeMrptSizesIt)
{
    const auto data = inFrame(imageObservation(pattern(40, 30, mrpt::img::CH_GRAY)));
    expectReads(data);
    // External-storage flag, colour flag, then width and height.
    const size_t width = imageData(data) + 2;
    ASSERT_EQ(getU32(data, width), 40u);
    expectRefused(data, width, 0x40000000u, "pixels of a grey image");
    expectRefused(data, width + 4, 0xFFFFFFF0u, "pixels of a grey image");  // a negative height
}

// The label of a stereo observation lies after its images (v6: one to three, as two
// flags after the left one say), the timestamp and the right camera's pose; images of
// 8 KB put it beyond the 4 KiB the guard looks ahead by default.
TEST(RawlogHostileSensorsTest, StereoImagesLabelIsChecked)
{
    for (const int width : {8, 100})
        for (const bool right : {false, true})
            for (const bool disparity : {false, true})
            {
                SCOPED_TRACE("width " + std::to_string(width) + ", right " + (right ? "yes" : "no") +
                             ", disparity " + (disparity ? "yes" : "no"));
                mrpt::obs::CObservationStereoImages obs;
                obs.imageLeft = pattern(width, 80, mrpt::img::CH_GRAY);
                obs.hasImageRight = right;
                obs.hasImageDisparity = disparity;
                if (right) obs.imageRight = pattern(width, 80, mrpt::img::CH_GRAY);
                if (disparity) obs.imageDisparity = pattern(width, 80, mrpt::img::CH_GRAY);
                obs.leftCamera.cameraName = "left_cam";
                expectLabelGuarded(obs, "stereo_rig");
            }
}

// An RGB-D 360 observation holds two range images, each sized from its two dimensions.
TEST(RawlogHostileSensorsTest, Rgbd360RangeImagesAreChecked)
{
    mrpt::obs::CObservationRGBD360 obs;
    obs.sensorLabel = "rgbd360";
    obs.hasRangeImage = true;
    obs.rangeImages[0].setZero(3, 4);
    obs.rangeImages[1].setZero(2, 5);
    const auto data = inFrame(obs);
    expectReads(data);
    const size_t first = find(data, std::string("\x03\0\0\0\x04\0\0\0", 8));
    const size_t second = first + 8 + 3 * 4 * 2;
    ASSERT_EQ(getU32(data, second), 2u);
    ASSERT_EQ(getU32(data, second + 4), 5u);
    expectRefused(data, first, 0xFFFFu, "range image pixels");
    expectRefused(data, second + 4, 0xFFFFu, "range image pixels");
}

// The features of a stereo-features observation follow two cameras and two poses (a
// camera name of 5,000 characters puts them beyond the default look-ahead).
TEST(RawlogHostileSensorsTest, StereoFeaturesCountAndLabelAreChecked)
{
    for (const size_t name : {size_t{8}, size_t{5000}})
    {
        SCOPED_TRACE("camera name of " + std::to_string(name) + " characters");
        mrpt::obs::CObservationStereoImagesFeatures obs;
        obs.cameraLeft.cameraName = std::string(name, 'c');
        obs.sensorLabel = "stereo_features";
        obs.theFeatures.resize(3);
        const auto data = inFrame(obs);
        expectReads(data);
        const size_t label = lengthOf(data, "stereo_features");
        // Per feature four floats and an ID.
        const size_t count = label - 3 * 20 - 4;
        ASSERT_EQ(getU32(data, count), 3u);
        expectRefused(data, count, 0x40000000u, "stereo features");
        expectRefused(data, label, 0xF0000000u, "bytes of sensor label");
    }
}

TEST(RawlogHostileSensorsTest, JpegByteCountAndDecodedSizeAreChecked)
{
    const auto data = imageFrame(imageObservation(pattern(64, 48, mrpt::img::CH_RGB)), true);
    expectReads(data);
    // External-storage flag, colour flag, width, height, the JPEG's byte count.
    const size_t count = imageData(data) + 2 + 8;
    const uint32_t n = getU32(data, count);
    ASSERT_EQ(data[count + 4], 0xFF);
    ASSERT_EQ(data[count + 5], 0xD8) << "not a JPEG";
    expectRefused(data, count, 0x7FFFFFFFu, "bytes of JPEG data");
    // The frame header: FF C0, length, precision, height and width (big-endian).
    const size_t sof = find(data, std::string("\xFF\xC0", 2), count + 4);
    ASSERT_LT(sof, count + 4 + n);
    ASSERT_EQ(data[sof + 5] * 256 + data[sof + 6], 48);
    auto huge = data;
    for (const size_t at : {sof + 5, sof + 7})
    {
        huge[at] = 0xFD;  // 65,000
        huge[at + 1] = 0xE8;
    }
    expectCleanError(writeGz(huge), huge, "entry 0", "a rawlog image may decode to");
}

TEST(RawlogHostileSensorsTest, HugeRawColourImageIsRefused)
{
    const auto data = imageFrame(imageObservation(pattern(16, 12, mrpt::img::CH_RGB)), false);
    expectReads(data);
    // Negative width and height mark the raw rows.
    const size_t width = imageData(data) + 2;
    ASSERT_EQ(static_cast<int32_t>(getU32(data, width)), -16);
    expectRefused(data, width, static_cast<uint32_t>(-0x20000000), "pixels of a raw colour image");
}

TEST(RawlogHostileSensorsTest, HugeExternalImageFileNameIsRefused)
{
    mrpt::img::CImage img;
    img.setExternalStorage("images/left_000123.png");
    const auto data = inFrame(imageObservation(img));
    expectReads(data);
    expectRefused(data, lengthOf(data, "images/left_000123.png"), 0xF0000000u, "bytes of image file name");
}

// A version-0 image (MRPT before 0.5.5-era JPEG storage) declares its size and, apart,
// the bytes of data: MRPT sizes the image from the first and reads the second into it.
TEST(RawlogHostileSensorsTest, OldImageDataLongerThanItsImageIsRefused)
{
    const auto grey = inFrame(imageObservation(pattern(4, 2, mrpt::img::CH_GRAY)));
    const size_t v = imageData(grey) - 1;
    // v9 grey: flags (2), width, height, origin, size, depth (20), no-zip flag, 8 bytes.
    const size_t end = v + 1 + 2 + 20 + 1 + 8;
    ASSERT_EQ(grey[end], 0x88) << "end flag of the image";
    const auto withV0 = [&](uint32_t length, size_t bytes, uint32_t channels = 1)
    {
        std::vector<uint8_t> d(grey.begin(), grey.begin() + static_cast<std::ptrdiff_t>(v));
        d.push_back(0);  // version 0
        for (const uint32_t x : {4u, 2u, channels})
        {
            d.resize(d.size() + 4);
            putU32(d, d.size() - 4, x);
        }
        d.push_back(0);  // origin
        d.resize(d.size() + 4);
        putU32(d, d.size() - 4, length);
        d.insert(d.end(), bytes, 0x55);
        d.insert(d.end(), grey.begin() + static_cast<std::ptrdiff_t>(end), grey.end());
        return d;
    };
    expectReads(withV0(8, 8));
    const auto over = withV0(4096, 4096);
    expectCleanError(writeGz(over), over, "entry 0", "4096 bytes of data for it");
    const auto wide = withV0(8, 8);
    expectRefused(wide, v + 1, 0x7FFFFFFFu, "pixels of an old-format image");
    // MRPT casts the channel count to a byte (257 is 1 channel: 8 bytes, not 2,056), and
    // OpenCV reads 0 channels as 512.
    const auto cast = withV0(2056, 2056, 257);
    expectCleanError(writeGz(cast), cast, "entry 0", "2056 bytes of data for it");
    const auto none = withV0(8, 8, 0);
    expectCleanError(writeGz(none), none, "entry 0", "pixels of an old-format image");
}

// A grey image's depth (v9) that MRPT does not define: MRPT maps it to a type OpenCV reads
// as 1,024 bytes a pixel.
TEST(RawlogHostileSensorsTest, UndefinedGreyImageDepthIsRefused)
{
    const auto data = inFrame(imageObservation(pattern(6, 4, mrpt::img::CH_GRAY)));
    // Flags, width, height, origin, size, then the depth.
    const size_t depth = imageData(data) + 2 + 16;
    ASSERT_EQ(getU32(data, depth), 0u) << "8-bit unsigned";
    expectRefused(data, depth, 7, "pixel depth 7, which MRPT does not define");
}

// The frame header of a JPEG 5 KB in, behind an application segment: beyond the 4 KiB
// the stream looks ahead by default, so the walk to it uses a wider window.
TEST(RawlogHostileSensorsTest, JpegFrameHeaderBehindALargeSegmentIsChecked)
{
    auto data = imageFrame(imageObservation(pattern(64, 48, mrpt::img::CH_RGB)), true);
    const size_t count = imageData(data) + 2 + 8;
    const size_t soi = count + 4;
    ASSERT_EQ(data[soi + 1], 0xD8);
    std::vector<uint8_t> app{0xFF, 0xE1, 5000 >> 8, 5000 & 0xFF};
    app.resize(2 + 5000, 'x');
    data.insert(data.begin() + static_cast<std::ptrdiff_t>(soi + 2), app.begin(), app.end());
    putU32(data, count, getU32(data, count) + static_cast<uint32_t>(app.size()));
    expectReads(data);
    const size_t sof = find(data, std::string("\xFF\xC0", 2), soi + 2 + app.size());
    for (const size_t at : {sof + 5, sof + 7})
    {
        data[at] = 0xFD;  // 65,000
        data[at + 1] = 0xE8;
    }
    expectCleanError(writeGz(data), data, "entry 0", "a rawlog image may decode to");
}

}  // namespace

namespace
{
// A battery state is not read by the pipeline, but MRPT builds it inside a frame and sized
// the other batteries' voltages from the count alone (found by the long rawlog_fuzz run:
// a frame's observation renamed to this class, 7.8 GB; regressions/rawlog/
// oom_battery_state_voltage_count).
TEST(RawlogHostileSensorsTest, HugeBatteryVoltageCountIsRefused)
{
    mrpt::obs::CObservationBatteryState obs;
    obs.sensorLabel = "battery";
    obs.voltageOtherBatteries.resize(2);
    obs.voltageOtherBatteries[1] = 12.5;
    obs.voltageOtherBatteriesValid = {true, false};
    const auto data = inFrame(obs);
    expectReads(data);
    // Version byte, two doubles, two flags, then the count.
    const size_t count = find(data, "mrpt::obs::CObservationBatteryState") + 35 + 1 + 18;
    ASSERT_EQ(getU32(data, count), 2u);
    expectRefused(data, count, 0x3A749B72u, "battery voltages");
    expectRefused(data, count + 4 + 16, 0x7FFFFFF0u, "battery validity flags");
    expectRefused(data, lengthOf(data, obs.sensorLabel), 0xF0000000u, "bytes of sensor label");
}

// MRPT builds whatever registered class an entry or a frame's element names before the
// cast that finds it is none (a map, a scene object), with the sizes it declares: such
// classes are refused at their name.
TEST(RawlogHostileSensorsTest, EntriesAndFrameElementsOfOtherClassesAreRefused)
{
    const auto entry = serialised(mrpt::poses::CPose2D(1, 2, 0.3));
    expectCleanError(writeGz(entry), entry, "entry 0", "holds a 'CPose2D' where a rawlog entry belongs");

    // A frame whose comment is renamed to CPoint2D (as long a name as CPose2D's).
    mrpt::obs::CObservationComment comment;
    comment.text = "x";
    auto data = inFrame(comment);
    expectReads(data);
    const std::string from = "mrpt::obs::CObservationComment";
    const std::string to = "mrpt::poses::CPose2D";
    const size_t at = find(data, from) - 1;
    std::vector<uint8_t> renamed(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(at));
    renamed.push_back(static_cast<uint8_t>(0x80 | to.size()));
    renamed.insert(renamed.end(), to.begin(), to.end());
    renamed.push_back(1);  // CPose2D version 1: three doubles
    renamed.resize(renamed.size() + 24);
    renamed.push_back(0x88);
    renamed.push_back(0x88);  // the frame's end flag
    expectCleanError(writeGz(renamed), renamed, "entry 0",
                     "holds a 'CPose2D' where an observation of a CSensoryFrame belongs");
}
}  // namespace

namespace
{
// MRPT's own sample rawlogs (package mrpt-common): 2D and 3D lidars, Velodyne packets,
// RGB-D, GPS with comments, beacon ranges, landmarks. The guard must refuse none of
// them: each is read to its end.
TEST(RawlogHostileSensorsTest, MrptSampleRawlogsReadThroughTheGuard)
{
    namespace fs = std::filesystem;
    const fs::path dir = "/usr/share/mrpt/datasets";
    if (!fs::is_directory(dir)) GTEST_SKIP() << dir << " not installed (package mrpt-common)";
    // Rotating scans are implemented in mrpt-maps: linked, their class is registered.
    ASSERT_NE(mrpt::obs::CObservationRotatingScan::GetRuntimeClassIdStatic().className, nullptr);
    size_t files = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir))
    {
        if (e.path().extension() != ".rawlog") continue;
        ++files;
        size_t entries = 0;
        EXPECT_NO_THROW({
            hymm::io::RawlogReader reader(e.path().string());
            hymm::io::RawlogEntry entry;
            while (reader.next(entry)) ++entries;
        }) << e.path();
        EXPECT_GT(entries, 0u) << e.path();
    }
    EXPECT_GT(files, 0u);
}
}  // namespace

namespace
{
size_t afterName(const std::vector<uint8_t>& d, const std::string& qualified)
{
    return find(d, std::string(1, static_cast<char>(0x80 | qualified.size())) + qualified) + 1 + qualified.size();
}

// Offset just past the CPose3D object (version 3: 12 doubles) that starts at `at`.
size_t pastPose(const std::vector<uint8_t>& d, size_t at)
{
    EXPECT_EQ(d[at], 0x80 | 20) << "mrpt::poses::CPose3D";
    EXPECT_EQ(d[at + 21], 3) << "CPose3D version";
    return at + 22 + 96 + 1;
}

TEST(RawlogHostileSensorsTest, HugeVelodynePacketCountIsRefused)
{
    mrpt::obs::CObservationVelodyneScan obs;
    obs.sensorLabel = "velodyne";
    obs.scan_packets.resize(2);
    obs.point_cloud.x = {1.0f, 2.0f};
    obs.point_cloud.y = {0.5f, 0.5f};
    obs.point_cloud.z = {0.1f, 0.2f};
    obs.point_cloud.intensity = {10, 20};
    const auto data = inFrame(obs);
    expectReads(data);
    // Version, timestamp, label, two doubles, the sensor pose, then the packet count.
    const size_t label = afterName(data, "mrpt::obs::CObservationVelodyneScan") + 1 + 8;
    ASSERT_EQ(getU32(data, label), obs.sensorLabel.size());
    const size_t packets = pastPose(data, label + 4 + obs.sensorLabel.size() + 16);
    ASSERT_EQ(getU32(data, packets), 2u);
    expectRefused(data, packets, 0x00FFFFFFu, "Velodyne packets");
    const size_t calib = packets + 4 + 2 * sizeof(mrpt::obs::CObservationVelodyneScan::TVelodyneRawPacket);
    ASSERT_EQ(getU32(data, calib), 0u);
    expectRefused(data, calib + 4, 0x7FFFFFFFu, "point x coordinates");
    expectRefused(data, calib + 4 + 4 + 8 + 4 + 8 + 4 + 8, 0xF0000000u, "point intensities");
}

TEST(RawlogHostileSensorsTest, Huge3DPointCountAndRangeImageAreRefused)
{
    mrpt::obs::CObservation3DRangeScan obs;
    obs.sensorLabel = "rgbd";
    obs.hasPoints3D = true;
    obs.resizePoints3DVectors(3);
    obs.hasRangeImage = true;
    obs.rangeImage_setSize(4, 5);
    obs.rangeImage.setZero();
    obs.cameraParams.ncols = 5;  // the range image's size, as MRPT expects
    obs.cameraParams.nrows = 4;
    const auto data = inFrame(obs);
    expectReads(data);
    // Version, the maximum range, the sensor pose, the points flag, then the count.
    const size_t points = pastPose(data, afterName(data, "mrpt::obs::CObservation3DRangeScan") + 1 + 4) + 1;
    ASSERT_EQ(getU32(data, points), 3u);
    expectRefused(data, points, 0x40000000u, "3-D points");
    // Per point three floats and two uint16 indices; the range-image flag, the units.
    const size_t rows = points + 4 + 3 * 16 + 1 + 4;
    ASSERT_EQ(getU32(data, rows), 4u);
    ASSERT_EQ(getU32(data, rows + 4), 5u);
    expectRefused(data, rows, 0x80000000u, "range image pixels");
}

TEST(RawlogHostileSensorsTest, HugePointCloudIsRefused)
{
    mrpt::obs::CObservationPointCloud obs;
    obs.sensorLabel = "lidar3d";
    auto map = mrpt::maps::CSimplePointsMap::Create();
    map->insertPoint(1, 2, 3);
    map->insertPoint(4, 5, 6);
    obs.pointcloud = map;
    const auto data = inFrame(obs);
    expectReads(data);
    const size_t count = afterName(data, "mrpt::maps::CSimplePointsMap") + 1;
    ASSERT_EQ(getU32(data, count), 2u);
    expectRefused(data, count, 0x20000000u, "points");
}
}  // namespace

namespace
{
TEST(RawlogHostileSensorsTest, LabelsOfTheRarerClassesAreChecked)
{
    using namespace mrpt::obs;
    expectLabelGuarded(CObservationReflectivity(), "reflectivity_sensor");
    expectLabelGuarded(CObservationWirelessPower(), "wifi_power");
    expectLabelGuarded(CObservationWindSensor(), "anemometer");
    expectLabelGuarded(CObservationRobotPose(), "external_pose");
    expectLabelGuarded(CObservationSkeleton(), "kinect_skeleton");
    CObservationCANBusJ1939 can;
    can.m_data = {1, 2, 3};
    can.m_raw_frame = {'a', 'b'};
    expectLabelGuarded(can, "can_bus_0");
    const auto data = [&] { can.sensorLabel = "can_bus_0"; return inFrame(can); }();
    // PGN, five bytes, then the data count.
    const size_t count = afterName(data, "mrpt::obs::CObservationCANBusJ1939") + 1 + 7;
    ASSERT_EQ(getU32(data, count), 3u);
    expectRefused(data, count, 0x7FFFFFFFu, "CAN data bytes");
    expectRefused(data, count + 4 + 3, 0x7FFFFFFFu, "CAN raw frame bytes");
}

// A class whose serialised data starts with its count (after the version byte).
template <class Obs>
void expectLeadingCountGuarded(const Obs& obs, const std::string& qualified, uint32_t n, const std::string& what)
{
    const auto data = inFrame(obs);
    expectReads(data);
    const size_t count = afterName(data, qualified) + 1;
    ASSERT_EQ(getU32(data, count), n);
    expectRefused(data, count, 0x7FFFFFFFu, what);
}

TEST(RawlogHostileSensorsTest, CountsOfTheRarerClassesAreChecked)
{
    using namespace mrpt::obs;
    CObservationRFID rfid;
    rfid.tag_readings.resize(2);
    expectLeadingCountGuarded(rfid, "mrpt::obs::CObservationRFID", 2, "RFID tags");
    CObservationGasSensors gas;
    gas.m_readings.resize(2);
    expectLeadingCountGuarded(gas, "mrpt::obs::CObservationGasSensors", 2, "gas sensor readings");

    CObservation6DFeatures features;
    features.sensedFeatures.resize(1);
    const auto data = inFrame(features);
    expectReads(data);
    const size_t count = pastPose(data, afterName(data, "mrpt::obs::CObservation6DFeatures") + 1 + 8);
    ASSERT_EQ(getU32(data, count), 1u);
    expectRefused(data, count, 0x00FFFFFFu, "6-D features");
}

// A sensory frame holding one object of class `name` (qualified) and `version`, whose
// serialised data is `body` (the end flag is added): for layouts MRPT 2.5 reads but no
// longer writes.
std::vector<uint8_t> inFrameAsWritten(const std::string& name, uint8_t version, const std::vector<uint8_t>& body)
{
    mrpt::obs::CSensoryFrame sf;
    auto data = serialised(sf);  // header, version, a zero count, end flag
    const size_t n = afterName(data, "mrpt::obs::CSensoryFrame") + 1;
    putU32(data, n, 1);
    std::vector<uint8_t> obs{static_cast<uint8_t>(0x80 | name.size())};
    obs.insert(obs.end(), name.begin(), name.end());
    obs.push_back(version);
    obs.insert(obs.end(), body.begin(), body.end());
    obs.push_back(0x88);
    data.insert(data.begin() + static_cast<std::ptrdiff_t>(n + 4), obs.begin(), obs.end());
    return data;
}

void appendU32(std::vector<uint8_t>& bytes, uint32_t x)
{
    bytes.resize(bytes.size() + 4);
    putU32(bytes, bytes.size() - 4, x);
}

// Before version 4 the RFID tag count is decimal text, parsed with atoi into a uint32:
// "-1" is 4,294,967,295 tags.
TEST(RawlogHostileSensorsTest, RfidTagCountAsTextIsChecked)
{
    const auto rfidV3 = [](const std::string& count)
    {
        std::vector<uint8_t> body;
        appendU32(body, static_cast<uint32_t>(count.size()));
        body.insert(body.end(), count.begin(), count.end());
        body.resize(body.size() + 8, 0);  // one tag's power
        appendU32(body, 0);               // its EPC
        appendU32(body, 0);               // its antenna port
        appendU32(body, 0);               // the label
        body.resize(body.size() + 8, 0);  // the timestamp
        const auto pose = serialised(mrpt::poses::CPose3D());
        body.insert(body.end(), pose.begin(), pose.end());
        return inFrameAsWritten("mrpt::obs::CObservationRFID", 3, body);
    };
    expectReads(rfidV3("1"));
    for (const char* count : {"-1", "2000000000", "99999999999999999999"})
    {
        const auto data = rfidV3(count);
        expectCleanError(writeGz(data), data, "entry 0", "RFID tags");
    }
}

// Versions 0 and 1 of a gas-sensor observation hold 16 voltages as a float vector, which
// MRPT sizes from its count before it checks the count is 16 (the fuzzer's 68-byte input
// made it allocate 7.8 GB).
TEST(RawlogHostileSensorsTest, GasSensorVoltagesOfVersionsZeroAndOneAreChecked)
{
    for (const uint8_t version : {0, 1})
    {
        std::vector<uint8_t> body;
        appendU32(body, 16);
        body.resize(body.size() + 16 * 4, 0);
        const auto data = inFrameAsWritten("mrpt::obs::CObservationGasSensors", version, body);
        expectReads(data);
        const size_t count = afterName(data, "mrpt::obs::CObservationGasSensors") + 1;
        expectRefused(data, count, 0x7463656Cu, "gas sensor voltages");
    }
}

TEST(RawlogHostileSensorsTest, RotatingScanImagesAreChecked)
{
    mrpt::obs::CObservationRotatingScan obs;
    obs.sensorLabel = "ouster";
    obs.lidarModel = "OS1";
    obs.rowCount = 4;
    obs.columnCount = 5;
    obs.rangeImage.setZero(4, 5);
    obs.intensityImage.setZero(4, 5);
    const auto data = inFrame(obs);
    expectReads(data);
    // After the lidar model: two doubles, the sensor pose, a timestamp and a flag.
    const size_t dims = pastPose(data, find(data, obs.lidarModel) + obs.lidarModel.size() + 16) + 9;
    ASSERT_EQ(data[dims], 5);
    ASSERT_EQ(data[dims + 2], 4);
    expectRefused(data, dims, 0xFFFFFFFFu, "range image pixels");
    expectRefused(data, dims + 4 + 2 * 20, 0xFFFFFFFFu, "intensity image pixels");
    expectRefused(data, lengthOf(data, obs.lidarModel), 0xF0000000u, "bytes of lidar model");
}
}  // namespace

namespace
{
// The camera's name (TCamera) and the label after the image, whose offset follows from
// the image's layout (raw grey, raw colour, JPEG, external file).
TEST(RawlogHostileSensorsTest, CameraNameAndImageObservationLabelAreChecked)
{
    for (int variant = 0; variant < 4; ++variant)
    {
        mrpt::img::CImage img;
        if (variant == 0) img = pattern(6, 4, mrpt::img::CH_GRAY);
        if (variant == 1 || variant == 2) img = pattern(16, 12, mrpt::img::CH_RGB);
        if (variant == 3) img.setExternalStorage("cam/0001.png");
        auto obs = imageObservation(img);
        obs.sensorLabel = "front_camera";
        obs.cameraParams.cameraName = "left_cam";
        const auto data = imageFrame(obs, variant == 2);
        SCOPED_TRACE(variant);
        expectReads(data);
        expectRefused(data, lengthOf(data, "left_cam"), 0xF0000000u, "bytes of camera name");
        expectRefused(data, lengthOf(data, "front_camera"), 0xF0000000u, "bytes of sensor label");
    }
}
}  // namespace

namespace
{
// A GPS observation's messages are walked as MRPT reads them: a NovAtel generic frame
// sizes its body from a count, then MRPT reads 4 bytes into it whatever its size. The
// frame comes after a GGA, a BESTPOS and a RANGECMP message of two records, which the
// walk must step over to find it. (The RANGECMP is spliced in as bytes: MRPT's class is
// packed, and constructing one is undefined behaviour that UBSan reports.)
TEST(RawlogHostileSensorsTest, NovatelFrameBehindOtherGpsMessagesIsChecked)
{
    using namespace mrpt::obs;
    CObservationGPS obs;
    obs.sensorLabel = "novatel";
    gnss::Message_NMEA_GGA gga;
    gga.fields.fix_quality = 4;
    obs.setMsg(gga);
    obs.setMsg(gnss::Message_NV_OEM6_BESTPOS());
    gnss::Message_NV_OEM6_GENERIC_FRAME frame;
    frame.msg_body = {0xAB, 0xCD, 0xEF, 0x12};
    obs.messages[gnss::NV_OEM6_GENERIC_FRAME].set(new gnss::Message_NV_OEM6_GENERIC_FRAME(frame));
    auto data = inFrame(obs);
    expectReads(data);
    // The message count (3) before the GGA's type (10).
    const size_t messages = find(data, std::string("\x03\0\0\0\x0A\0\0\0", 8));
    putU32(data, messages, 4);
    // RANGECMP: its type, the expected length, the header, two records.
    std::vector<uint8_t> rangecmp(4 + 4 + sizeof(gnss::nv_oem6_header_t) + 4, 0);
    putU32(rangecmp, 0, gnss::NV_OEM6_RANGECMP);
    putU32(rangecmp, rangecmp.size() - 4, 2);
    rangecmp.resize(rangecmp.size() + 2 * sizeof(gnss::Message_NV_OEM6_RANGECMP::TCompressedRangeLog), 0);
    const size_t body = find(data, std::string("\xAB\xCD\xEF\x12", 4));
    const size_t frame_type = body - 4 - sizeof(gnss::nv_oem6_header_t) - 4;
    ASSERT_EQ(getU32(data, frame_type), static_cast<uint32_t>(gnss::NV_OEM6_GENERIC_FRAME));
    data.insert(data.begin() + static_cast<std::ptrdiff_t>(frame_type), rangecmp.begin(), rangecmp.end());
    expectReads(data);
    const size_t count = body + rangecmp.size() - 4;
    ASSERT_EQ(getU32(data, count), 4u);
    expectRefused(data, count, 2, "into which MRPT reads 4");
    expectRefused(data, count, 0x7FFFFFFFu, "bytes of a NovAtel frame");
}
}  // namespace

namespace
{
// A Topcon receiver's observation with a PZS message whose fix byte reads like an end
// flag.
mrpt::obs::CObservationGPS topconWithPzs()
{
    mrpt::obs::CObservationGPS gps;
    gps.sensorLabel = "topcon";
    mrpt::obs::gnss::Message_TOPCON_PZS pzs;
    pzs.Fix = 0x88;
    pzs.hasPosCov = true;
    gps.setMsg(pzs);
    return gps;
}

// Topcon messages have no byte count: the walk steps over a PZS (its covariances are
// matrix objects) and checks the three counted vectors of a SATS, then goes on to a
// NovAtel frame after them.
TEST(RawlogHostileSensorsTest, TopconMessagesAreWalkedAndSatelliteCountsChecked)
{
    using namespace mrpt::obs;
    CObservationGPS obs = topconWithPzs();
    gnss::Message_TOPCON_SATS sats;
    sats.USIs = {7, 8, 9};
    sats.ELs = {10, 20, 30};
    sats.AZs = {100, 200, 300};
    obs.setMsg(sats);
    gnss::Message_NV_OEM6_GENERIC_FRAME frame;
    frame.msg_body = {0xAB, 0xCD, 0xEF, 0x12};
    obs.messages[gnss::NV_OEM6_GENERIC_FRAME].set(new gnss::Message_NV_OEM6_GENERIC_FRAME(frame));
    const auto data = inFrame(obs);
    expectReads(data);
    const size_t ids = find(data, std::string("\x03\0\0\0\x07\x08\x09", 7));
    ASSERT_EQ(getU32(data, ids - 4), static_cast<uint32_t>(gnss::TOPCON_SATS));
    expectRefused(data, ids, 0x7FFFFFFFu, "Topcon satellite IDs");
    expectRefused(data, ids + 7, 0x7FFFFFFFu, "Topcon satellite elevations");
    expectRefused(data, ids + 14, 0x7FFFFFFFu, "Topcon satellite azimuths");
    const size_t body = find(data, std::string("\xAB\xCD\xEF\x12", 4));
    ASSERT_EQ(getU32(data, body - 4), 4u);
    expectRefused(data, body - 4, 2, "into which MRPT reads 4");
}
}  // namespace

namespace
{
// MRPT decodes a JPEG with libjpeg's standard error handler, which calls exit(): a corrupt
// JPEG in a rawlog ended the reading program without an error (found by rawlog_fuzz:
// regressions/rawlog/exit_corrupt_jpeg). The guard decodes it first. Without the check
// the child exits with 1, which readInChild reports as "read without error".
TEST(RawlogHostileSensorsTest, CorruptJpegIsRefusedInsteadOfEndingTheProgram)
{
    const auto data = imageFrame(imageObservation(pattern(32, 24, mrpt::img::CH_RGB)), true);
    expectReads(data);
    const size_t soi = find(data, std::string("\xFF\xD8\xFF", 3));
    // A second start-of-image marker where the quantisation table's marker was.
    auto twoSoi = data;
    const size_t dqt = find(data, std::string("\xFF\xDB", 2), soi);
    twoSoi[dqt + 1] = 0xD8;
    expectCleanError(writeGz(twoSoi), twoSoi, "entry 0", "that libjpeg cannot decode");
    // Not a JPEG at all.
    auto notJpeg = data;
    notJpeg[soi] = 0x12;
    expectCleanError(writeGz(notJpeg), notJpeg, "entry 0", "that libjpeg cannot decode");
}
}  // namespace

namespace
{
// A uint8 field of value 0x88 inside a frame's observation looks like an end flag. A
// Topcon PZS message reads five status bytes and then a CMatrixF object: taking 0x88 for
// the GPS observation's end had that matrix checked as a frame element and the valid file
// refused. A CAN observation's data bytes (read one at a time) could, the other way, end
// the frame's checks early and let a planted map through.
TEST(RawlogHostileSensorsTest, ValueBytesLikeAnEndFlagDoNotEndAFrameElement)
{
    using namespace mrpt::obs;
    expectReads(inFrame(topconWithPzs()));

    CObservationCANBusJ1939 can;
    can.m_data = {0x88, 0x01};
    CSensoryFrame sf;
    sf.insert(CObservationCANBusJ1939::Create(can));
    auto comment = CObservationComment::Create();
    comment->text = "after the CAN frame";
    sf.insert(comment);
    const auto data = serialised(sf);
    expectReads(data);
    // The comment renamed to a points map (a name of the same length is not at hand, so
    // the map's name and a null payload replace the comment and the frame's end).
    const std::string map = "mrpt::maps::CSimplePointsMap";
    const size_t at = find(data, "mrpt::obs::CObservationComment") - 1;
    std::vector<uint8_t> planted(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(at));
    planted.push_back(static_cast<uint8_t>(0x80 | map.size()));
    planted.insert(planted.end(), map.begin(), map.end());
    planted.push_back(10);  // version
    planted.resize(planted.size() + 4, 0);  // no points
    planted.push_back(0x88);
    planted.push_back(0x88);
    expectCleanError(writeGz(planted), planted, "entry 0",
                     "holds a 'CSimplePointsMap' where an observation of a CSensoryFrame belongs");
}
}  // namespace

namespace
{
// A version-0 RGB-D scan: no points flag, no image flags, a validity byte per point. The
// last entry of a file, with an empty label, ends exactly where the minimum tail ends.
TEST(RawlogHostileSensorsTest, OldestRgbdScanReadsAndItsCountIsChecked)
{
    const auto scanV0 = [](uint32_t declared)
    {
        const std::string name = "mrpt::obs::CObservation3DRangeScan";
        std::vector<uint8_t> obs{static_cast<uint8_t>(0x80 | name.size())};
        obs.insert(obs.end(), name.begin(), name.end());
        obs.push_back(0);               // version 0
        obs.resize(obs.size() + 4, 0);  // maximum range
        const auto pose = serialised(mrpt::poses::CPose3D());
        obs.insert(obs.end(), pose.begin(), pose.end());
        const auto u32 = [&](uint32_t x) { obs.resize(obs.size() + 4); putU32(obs, obs.size() - 4, x); };
        u32(declared);
        obs.resize(obs.size() + 2 * 13, 0);  // two points: x, y, z and a validity byte each
        obs.resize(obs.size() + 4 + 8, 0);   // stdError, timestamp
        u32(0);                              // an empty label
        obs.push_back(0x88);
        mrpt::obs::CSensoryFrame sf;
        auto data = serialised(sf);
        const size_t n = afterName(data, "mrpt::obs::CSensoryFrame") + 1;
        putU32(data, n, 1);
        data.insert(data.begin() + static_cast<std::ptrdiff_t>(n + 4), obs.begin(), obs.end());
        return data;
    };
    expectReads(scanV0(2));
    const auto huge = scanV0(0x10000000);
    expectCleanError(writeGz(huge), huge, "entry 0", "3-D points");
}
}  // namespace

namespace
{
// A point-cloud observation's label and external file name are checked, and its cloud
// (read through a points-map pointer, built before the cast) must be a points map.
TEST(RawlogHostileSensorsTest, PointCloudLabelFileAndCloudClassAreChecked)
{
    mrpt::obs::CObservationPointCloud obs;
    auto map = mrpt::maps::CSimplePointsMap::Create();
    map->insertPoint(1, 2, 3);
    obs.pointcloud = map;
    expectLabelGuarded(obs, "velodyne_cloud");

    obs.sensorLabel = "velodyne_cloud";
    const auto data = inFrame(obs);
    const std::string from = "mrpt::maps::CSimplePointsMap";
    const std::string to = "mrpt::poses::CPose2D";  // planted: built, then cast to null
    const size_t at = find(data, from) - 1;
    std::vector<uint8_t> planted(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(at));
    planted.push_back(static_cast<uint8_t>(0x80 | to.size()));
    planted.insert(planted.end(), to.begin(), to.end());
    planted.push_back(1);
    planted.resize(planted.size() + 24, 0);
    planted.insert(planted.end(), {0x88, 0x88, 0x88});  // the pose's, the observation's and the frame's end
    expectCleanError(writeGz(planted), planted, "entry 0",
                     "holds a 'CPose2D' where the cloud of a CObservationPointCloud belongs");

    mrpt::obs::CObservationPointCloud external;
    external.sensorLabel = "lidar";
    external.setAsExternalStorage("clouds/0001.bin", mrpt::obs::CObservationPointCloud::ExternalStorageFormat::KittiBinFile);
    const auto ext = inFrame(external);
    expectReads(ext);
    expectRefused(ext, lengthOf(ext, "clouds/0001.bin"), 0xF0000000u, "bytes of point cloud file name");
}
}  // namespace

namespace
{
// Version 2 of a Velodyne scan adds per-point vectors, two of them written as generic
// containers (a "std::vector" string and a type-name string before the count): the
// per-point timestamps were a 29 GB allocation found by rawlog_fuzz within 60 s.
TEST(RawlogHostileSensorsTest, VelodynePerPointVectorsAreChecked)
{
    mrpt::obs::CObservationVelodyneScan obs;
    obs.sensorLabel = "vlp16";
    obs.point_cloud.x = {1.0f, 2.0f};
    obs.point_cloud.y = {0.5f, 0.5f};
    obs.point_cloud.z = {0.1f, 0.2f};
    obs.point_cloud.intensity = {10, 20};
    obs.point_cloud.timestamp = {mrpt::Clock::now(), mrpt::Clock::now()};
    obs.point_cloud.azimuth = {0.1f, 0.2f};
    obs.point_cloud.laser_id = {3, 4};
    obs.point_cloud.pointsForLaserID = {{0}, {1}};
    const auto data = inFrame(obs);
    expectReads(data);
    const size_t name = find(data, "std::vector") - 4;
    ASSERT_EQ(getU32(data, name), 11u);
    const size_t type = name + 4 + 11;
    const size_t stamps = type + 4 + getU32(data, type);
    ASSERT_EQ(getU32(data, stamps), 2u);
    expectRefused(data, name, 0x7FFFFFF0u, "bytes of a container name");
    expectRefused(data, stamps, 0x40000000u, "point timestamps");
    const size_t azimuths = stamps + 4 + 2 * 8;
    ASSERT_EQ(getU32(data, azimuths), 2u);
    expectRefused(data, azimuths + 4 + 2 * 4, 0x7FFFFFFFu, "point laser ids");
    const size_t outer = find(data, "std::vector", azimuths) - 4;
    const size_t lists = outer + 4 + 11 + 4 + getU32(data, outer + 4 + 11);
    ASSERT_EQ(getU32(data, lists), 2u);
    expectRefused(data, lists, 0x7FFFFFFFu, "lasers' point lists");
}
}  // namespace

namespace
{
// A JPEG of 2 components, which libjpeg encodes and decodes (an "unknown" colour space):
// MRPT sizes a colour image and copies 3 bytes a pixel out of libjpeg's 2-byte pixels.
std::vector<uint8_t> twoComponentJpeg(int w, int h)
{
    jpeg_compress_struct cinfo{};
    jpeg_error_mgr jerr{};
    cinfo.err = jpeg_std_error(&jerr);
    jpeg_create_compress(&cinfo);
    unsigned char* buf = nullptr;
    unsigned long size = 0;
    jpeg_mem_dest(&cinfo, &buf, &size);
    cinfo.image_width = static_cast<JDIMENSION>(w);
    cinfo.image_height = static_cast<JDIMENSION>(h);
    cinfo.input_components = 2;
    cinfo.in_color_space = JCS_UNKNOWN;
    jpeg_set_defaults(&cinfo);
    jpeg_start_compress(&cinfo, TRUE);
    std::vector<uint8_t> row(static_cast<size_t>(2 * w), 100);
    while (cinfo.next_scanline < cinfo.image_height)
    {
        JSAMPROW r = row.data();
        jpeg_write_scanlines(&cinfo, &r, 1);
    }
    jpeg_finish_compress(&cinfo);
    std::vector<uint8_t> out(buf, buf + size);
    jpeg_destroy_compress(&cinfo);
    std::free(buf);
    return out;
}

TEST(RawlogHostileSensorsTest, TwoComponentJpegIsRefused)
{
    const auto data = imageFrame(imageObservation(pattern(16, 12, mrpt::img::CH_RGB)), true);
    const size_t count = imageData(data) + 2 + 8;
    const uint32_t n = getU32(data, count);
    const auto jpeg = twoComponentJpeg(16, 12);
    std::vector<uint8_t> swapped(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(count));
    swapped.resize(swapped.size() + 4);
    putU32(swapped, count, static_cast<uint32_t>(jpeg.size()));
    swapped.insert(swapped.end(), jpeg.begin(), jpeg.end());
    swapped.insert(swapped.end(), data.begin() + static_cast<std::ptrdiff_t>(count + 4 + n), data.end());
    expectCleanError(writeGz(swapped), swapped, "entry 0", "2 colour components, which MRPT reads as 3");
}
}  // namespace

namespace
{
// A raw DAQ observation: the label and 13 sample vectors, the channel count and the
// interleaving flag between the 5th and the 6th. The counts of the vectors of 2, 4 and
// 8-byte samples tested here are set just beyond what the rest of the file holds at their
// own element size (and within it at 1 byte), so the test fails if the guard takes their
// element size, or their place in the chain, wrong; the 1-byte ones just beyond the bytes
// left.
TEST(RawlogHostileSensorsTest, RawDaqVectorsAreChecked)
{
    mrpt::obs::CObservationRawDAQ obs;
    obs.AIN_8bits = {1, 2};
    obs.AIN_double = {0.5, 1.5, 2.5};
    obs.AOUT_8bits = {7};
    obs.CNTRIN_double = {3.0, 4.0};
    expectLabelGuarded(obs, "daq_board");
    obs.sensorLabel = "daq_board";
    // Room for the counts before it to be cut by element size: 40 KB of digital outputs.
    obs.DOUT.assign(40000, 3);
    const auto data = inFrame(obs);
    expectReads(data);
    // The smallest count of `element`-byte samples that the bytes after it cannot hold.
    const auto beyond = [&](size_t at, size_t element)
    { return static_cast<uint32_t>((data.size() - at - 4) / element + 1); };
    // After the label, the timestamp and the sample rate: the 8-bit inputs.
    const size_t ain8 = lengthOf(data, "daq_board") + 4 + 9 + 16;
    ASSERT_EQ(getU32(data, ain8), 2u);
    expectRefused(data, ain8, beyond(ain8, 1), "DAQ samples of AIN_8bits");
    // AIN_16bits, AIN_32bits and AIN_float are empty; then AIN_double's count.
    const size_t ain16 = ain8 + 4 + 2;
    ASSERT_EQ(getU32(data, ain16), 0u);
    expectRefused(data, ain16, beyond(ain16, 2), "DAQ samples of AIN_16bits");
    const size_t ain32 = ain16 + 4;
    expectRefused(data, ain32, beyond(ain32, 4), "DAQ samples of AIN_32bits");
    const size_t ain_float = ain16 + 2 * 4;
    expectRefused(data, ain_float, beyond(ain_float, 4), "DAQ samples of AIN_float");
    const size_t ain_double = ain16 + 3 * 4;
    ASSERT_EQ(getU32(data, ain_double), 3u);
    expectRefused(data, ain_double, beyond(ain_double, 8), "DAQ samples of AIN_double");
    // The channel count and the interleaving flag (3 B), then the outputs.
    const size_t aout8 = ain_double + 4 + 3 * 8 + 3;
    ASSERT_EQ(getU32(data, aout8), 1u);
    const size_t aout16 = aout8 + 4 + 1;
    expectRefused(data, aout16, beyond(aout16, 2), "DAQ samples of AOUT_16bits");
    const size_t aout_double = aout8 + 4 + 1 + 2 * 4;
    expectRefused(data, aout_double, beyond(aout_double, 8), "DAQ samples of AOUT_double");
    const size_t dout = aout8 + 4 + 1 + 4 * 4;
    ASSERT_EQ(getU32(data, dout), 40000u);
    expectRefused(data, dout, beyond(dout, 1), "DAQ samples of DOUT");
    const size_t cntrin_double = dout + 4 + 40000 + 4;
    ASSERT_EQ(getU32(data, cntrin_double), 2u);
    expectRefused(data, cntrin_double, 0x10000000u, "DAQ samples of CNTRIN_double");
}
}  // namespace
