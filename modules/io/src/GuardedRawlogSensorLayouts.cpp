// GuardedRawlogStream: where the counts lie in the serialised objects of MRPT classes that
// HYMM does not read but MRPT builds inside sensory frames, to count them by class name
// (comments, beacon and range finders, IMUs, GPS receivers, battery states, Velodyne and
// RGB-D scans, point clouds, every image of a camera, stereo or RGB-D observation, and what
// follows the poses of stereo observations). Offsets follow MRPT 2.5's serializeFrom() of
// each class.
#include "GuardedRawlogStream.h"

#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/obs/VelodyneCalibration.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <string>

namespace hymm::io::detail
{
namespace
{

uint64_t bigEndian16(const uint8_t* b) { return (uint64_t{b[0]} << 8) | b[1]; }

// Bytes per pixel of MRPT's PixelDepth (D8U, D8S, D16U, D16S, D32S, D32F, D64F; other
// values are refused before this is asked).
uint64_t pixelDepthBytes(int32_t depth)
{
    static constexpr std::array<uint64_t, 7> kBytes{1, 1, 2, 2, 4, 4, 8};
    return kBytes[static_cast<size_t>(std::clamp(depth, 0, 6))];
}
}  // namespace

bool GuardedRawlogStream::armSensor(const ObjectHeader& h)
{
    const std::string& name = h.name;
    const int v = h.version;
    if (name == "CObservationComment" && v == 0)
        // The text, then the timestamp.
        checkpoints_.push_back(countAt(h, h.data, 1, 8, "bytes of comment text"));
    else if (name == "CObservationBeaconRanges" && v <= 3)
        // 3 floats, the count; per measurement a CPoint3D object, a float, a uint32; then
        // a pose object (v1+), the label (v2+), the timestamp (v3) (rawlog_fuzz: 47
        // million, 23 GB).
        checkpoints_.push_back(countAt(h, h.data + 12, kMinObjectBytes + 8,
                                       (v >= 1 ? kMinObjectBytes : 0) + (v >= 2 ? 4 : 0) + (v >= 3 ? 8 : 0),
                                       "beacon measurements"));
    else if (name == "CObservationRange" && v <= 3)
        armRange(h);
    else if (name == "CObservationIMU" && v <= 4)
        armImu(h);
    else if (name == "CObservationGPS" && (v == 10 || v == 11))
    {
        // Two timestamps, the label, the sensor pose (a CPose3D object), from v11 a flag,
        // then the message count. Messages are read one at a time (nothing is sized by
        // that count); their contents: armGpsMessages.
        checkpoints_.push_back(countAt(h, h.data + 16, 1, kMinPose3DBytes + (v >= 11 ? 1 : 0) + 4,
                                       "bytes of sensor label"));
        armGpsMessages(h);
    }
    else if (name == "CObservationBatteryState" && v <= 2)
    {
        // Two doubles and two flags, then the other batteries' voltages (count, doubles)
        // and validity flags (a vector<bool>), the label (v1+), the timestamp (v2+)
        // (rawlog_fuzz: a frame's observation renamed to this class, 7.8 GB).
        const uint64_t label = v >= 1 ? 4 : 0, stamp = v >= 2 ? 8 : 0;
        checkpoints_.push_back(countAt(h, h.data + 18, 8, 4 + label + stamp, "battery voltages"));
        checkpoints_.back().then = {{{"battery validity flags", 0, 1, label + stamp + endFlagBytes(h)},
                                     {v >= 1 ? "bytes of sensor label" : nullptr, 0, 1, stamp + endFlagBytes(h)}}};
    }
    else if (name == "CObservationVelodyneScan" && v <= 2)
        armVelodyne(h);
    else if (name == "CObservation3DRangeScan" && v <= 10)
        arm3DScan(h);
    else if ((name == "CSimplePointsMap" && v >= 8 && v <= 10) || (name == "CColouredPointsMap" && v >= 8 && v <= 9))
        // The point count, then x, y and z as floats (a coloured map also sizes three
        // float colour channels per point: 24 B for 12 in the file), then the options.
        checkpoints_.push_back(countAt(h, h.data, 12, 0, "points"));
    else if (name == "CObservationPointCloud" && v == 0)
        armPointCloud(h);
    else if (name == "CPointsMapXYZI" && v == 0)
        checkpoints_.push_back(countAt(h, h.data, 16, 0, "points"));
    else if (name == "TCamera" && v >= 5 && v <= 6)
        // The focal length, 8 distortion and 4 intrinsic doubles, rows and columns
        // (uint32), the camera name, the distortion model (v6, a byte).
        checkpoints_.push_back(countAt(h, h.data + 8 + 64 + 32 + 8, 1, v >= 6 ? 1 : 0, "bytes of camera name"));
    else if (name == "CImage")
        armImage(h);
    else
        return armRare(h);
    return true;
}

void GuardedRawlogStream::armRange(const ObjectHeader& h)
{
    // Three floats, the count; per measurement (v3+) a uint16 sensor ID, a CPose3D object
    // and a float; then the label (v1+) and the timestamp (v2+). MRPT holds 64 bytes per
    // measurement, less than the smallest serialised one.
    const int v = h.version;
    const uint64_t at = h.data + 12;
    const uint64_t id = v >= 3 ? 2 : 0;
    const uint64_t stamp = v >= 2 ? 8 : 0;
    uint32_t n = 0;
    if (!peek(at, &n, 4)) return;  // a short read: MRPT reports it
    // One writer wrote every pose: the first gives the stride, and with it where the label
    // lies. Without a pose that parses, the count is checked against the smallest pose
    // object and the label is left unchecked.
    const uint64_t first = at + 4 + id;
    const uint64_t past = n > 0 ? skipObject(first) : 0;
    const uint64_t pose = past != 0 ? past - first : kMinPose3DBytes;
    Checkpoint c = countAt(h, at, id + pose + 4, (v >= 1 ? 4 : 0) + stamp, "range measurements");
    if (v >= 1 && (n == 0 || past != 0)) c.then[0] = {"bytes of sensor label", 0, 1, stamp + endFlagBytes(h)};
    checkpoints_.push_back(c);
}

void GuardedRawlogStream::armImu(const ObjectHeader& h)
{
    const uint64_t at = skipObject(h.data);  // the sensor pose, a CPose3D object
    if (at == 0) return;
    if (h.version == 4)
    {
        // Fixed arrays: a presence byte per field, the timestamp, a double per field; then
        // the label.
        constexpr uint64_t n = mrpt::obs::COUNT_IMU_DATA_FIELDS;
        checkpoints_.push_back(countAt(h, at + n + 8 + 8 * n, 1, 0, "bytes of sensor label"));
        return;
    }
    // v0-3: the presence flags (a vector<bool>: count, a byte each; MRPT allocates a byte
    // and a bit per flag), the timestamp, the measurements (count, then floats in v0,
    // doubles later), the label.
    Checkpoint c = countAt(h, at, 1, 8 + 4 + 4, "IMU presence flags");
    c.then[0] = {"IMU measurements", 8, h.version == 0 ? 4u : 8u, 4 + endFlagBytes(h)};
    c.then[1] = {"bytes of sensor label", 0, 1, endFlagBytes(h)};
    checkpoints_.push_back(c);
}

void GuardedRawlogStream::armVelodyne(const ObjectHeader& h)
{
    // The timestamp, the label, minimum and maximum range (doubles), the sensor pose (a
    // CPose3D object), the raw packets, the per-laser calibration, the point cloud's x, y,
    // z (float vectors) and intensities (bytes); from v1 a flag, from v2 the per-point
    // timestamps (a generic std::vector: its "std::vector" and type-name strings, then
    // the count, 8 B each), azimuths (floats) and laser ids (int16), and the points per
    // laser (a generic vector of generic vectors, at least 12 B each).
    using Velodyne = mrpt::obs::CObservationVelodyneScan;
    const uint64_t packet = sizeof(Velodyne::TVelodyneRawPacket);
    const uint64_t calib = sizeof(mrpt::obs::VelodyneCalibration::PerLaserCalib);
    checkpoints_.push_back(countAt(h, h.data + 8, 1, 16 + kMinPose3DBytes + 6 * 4, "bytes of sensor label"));
    uint32_t label = 0;
    if (!peek(h.data + 8, &label, 4) || label > total_) return;
    const uint64_t at = skipObject(h.data + 12 + label + 16);
    if (at == 0) return;
    const uint64_t end = endFlagBytes(h);
    const uint64_t v1 = h.version >= 1 ? 1 : 0;
    const uint64_t v2 = h.version >= 2 ? 8 * 4 : 0;  // the counts and lengths that follow
    Checkpoint c = countAt(h, at, packet, 5 * 4 + v1 + v2, "Velodyne packets");
    c.then = {{{"laser calibrations", 0, calib, 4 * 4 + v1 + v2},
               {"point x coordinates", 0, 4, 3 * 4 + v1 + v2},
               {"point y coordinates", 0, 4, 2 * 4 + v1 + v2},
               {"point z coordinates", 0, 4, 4 + v1 + v2},
               {"point intensities", 0, 1, v1 + v2 + end}}};
    if (h.version >= 2)
    {
        c.then[5] = {"bytes of a container name", 1, 1, 7 * 4 + end};
        c.then[6] = {"bytes of a container type", 0, 1, 6 * 4 + end};
        c.then[7] = {"point timestamps", 0, 8, 5 * 4 + end};
        c.then[8] = {"point azimuths", 0, 4, 4 * 4 + end};
        c.then[9] = {"point laser ids", 0, 2, 3 * 4 + end};
        c.then[10] = {"bytes of a container name", 0, 1, 2 * 4 + end};
        c.then[11] = {"bytes of a container type", 0, 1, 4 + end};
        c.then[12] = {"lasers' point lists", 0, 12, end};
    }
    checkpoints_.push_back(c);
}

void GuardedRawlogStream::arm3DScan(const ObjectHeader& h)
{
    // The maximum range (float), the sensor pose (a CPose3D object), the points flag (v1+)
    // and the points: count, x y z floats (a validity byte each in v0, two uint16 pixel
    // indices each from v8; MRPT holds 16 B per point); then (v1+) the range-image flag,
    // (v9+) the range units (float) and the range image: rows and columns of uint16 (older
    // versions store it as a CMatrixF object, checked as one). The tail holds at least
    // the two image flags (v1+), stdError, the timestamp and the label's length.
    const int v = h.version;
    const uint64_t at = skipObject(h.data + 4);
    if (at == 0) return;
    uint8_t has_points = 1;
    if (v >= 1 && !peek(at, &has_points, 1)) return;
    const uint64_t tail = (v >= 1 ? 2 : 0) + 4 + 8 + 4;
    const uint64_t image_gap = 1 + 4;  // the range-image flag and the units (v9+)
    const uint64_t points_at = at + (v >= 1 ? 1 : 0);
    if (!has_points)
    {
        if (v < 9) return;
        Checkpoint c = countAt(h, points_at + image_gap, 2, tail, "range image pixels");
        c.kind = Checkpoint::Matrix;
        checkpoints_.push_back(c);
        return;
    }
    Checkpoint c = countAt(h, points_at, 12 + (v == 0 ? 1 : 0) + (v >= 8 ? 4 : 0), tail, "3-D points");
    if (v >= 9) c.then[0] = {"range image pixels", image_gap, 2, tail + endFlagBytes(h), true};
    checkpoints_.push_back(c);
}

void GuardedRawlogStream::armImage(const ObjectHeader& h)
{
    const uint64_t end = armImageData(h);
    if (end == 0 || open_.empty() || open_.back().name != "CObservationImage") return;
    // The image of a CObservationImage (v3-4) is followed by the timestamp, in v3 the
    // focal length (a double), then the label. The observation's end flag is taken to be
    // in the image's format (one writer wrote both).
    const int v = open_.back().version;
    if (v < 3 || v > 4) return;
    checkpoints_.push_back(countAt(h, end + endFlagBytes(h) + 8 + (v == 3 ? 8 : 0), 1, 0, "bytes of sensor label"));
}

void GuardedRawlogStream::armAfterStereoPose(const ObjectHeader& h)
{
    // Read directly inside a stereo observation (v4-6) are the camera's pose, then, after
    // the images and the timestamp, the right camera's (CPose3DQuat objects; v4: CPose3D
    // objects, and the focal length, a double, after the second), then the label. Inside
    // a stereo-features observation (v0), after the two cameras (TCamera objects): the
    // right camera's and the sensor's poses, then per feature two pixels (4 floats) and an
    // ID (uint32), then the label and the timestamp. Waiting for the second pose's header
    // puts both right behind the read position, whatever the images' or cameras' sizes.
    Frame& parent = open_.back();
    const bool stereo = parent.name == "CObservationStereoImages" && parent.version >= 4 && parent.version <= 6;
    const bool features = parent.name == "CObservationStereoImagesFeatures" && parent.version == 0;
    if ((!stereo && !features) || ++parent.poses != 2) return;
    const uint64_t end = objectEnd(h);
    if (end == 0) return;
    if (stereo)
    {
        checkpoints_.push_back(countAt(h, end + (parent.version == 4 ? 8 : 0), 1, 0, "bytes of sensor label"));
        return;
    }
    checkpoints_.push_back(countAt(h, end, 20, 4 + 8, "stereo features"));
    checkpoints_.back().then[0] = {"bytes of sensor label", 0, 1, 8 + endFlagBytes(h)};
}

uint64_t GuardedRawlogStream::armImageData(const ObjectHeader& h)
{
    // CImage, in every camera, stereo and RGB-D observation. v6+ (and v100, written
    // without OpenCV) start with the external-storage flag; an external image holds only
    // its file name. Returns where the image's data ends (0 if not known).
    const int v = h.version;
    uint64_t at = h.data;
    if (v == 100 || (v >= 6 && v <= 9))
    {
        uint8_t external = 0;
        uint32_t len = 0;
        if (!peek(at, &external, 1)) return 0;
        if (external)
        {
            checkpoints_.push_back(countAt(h, at + 1, 1, 0, "bytes of image file name"));
            return peek(at + 1, &len, 4) ? at + 5 + len : 0;
        }
        ++at;
    }
    if (v == 0) return armRawImage(h);
    if (v == 1) return armJpeg(h, at);
    if (v < 2 || v > 9) return 0;
    uint8_t color = 0;
    if (!peek(at, &color, 1)) return 0;
    ++at;
    if (!color) return armGreyImage(h, at);
    if (v < 7) return armJpeg(h, at);
    std::array<int32_t, 2> f{};  // width, height
    // Colour from v7: width and height; both positive: a JPEG follows; both negative
    // (v8): the raw rows, 3 bytes per pixel.
    if (!peek(at, f.data(), 8)) return 0;
    if (f[0] >= 1 && f[1] >= 1) return armJpeg(h, at + 8);
    if (f[0] >= 0 || f[1] >= 0) return at + 8;  // an empty image: nothing sized
    const uint64_t pixels = uint64_t{static_cast<uint32_t>(-int64_t{f[0]})} * static_cast<uint32_t>(-int64_t{f[1]});
    checkpoints_.push_back(pixelsAt(h, at, pixels, 3, 8, "pixels of a raw colour image"));
    return at + 8 + 3 * pixels;
}

uint64_t GuardedRawlogStream::armGreyImage(const ObjectHeader& h, uint64_t at)
{
    const int v = h.version;
    std::array<int32_t, 5> f{};  // width, height, origin, size, depth
    // Grey: width, height, origin, size in bytes, the depth (v9), the compression
    // flag (v5+), the rows. MRPT sizes the image from the first two (and the depth).
    if (!peek(at, f.data(), v >= 9 ? 20 : 16)) return 0;
    if (v >= 9 && (f[4] < 0 || f[4] > 6))
    {
        // MRPT maps a depth it does not define to a type OpenCV reads as 1,024 bytes a
        // pixel; no writer produces one.
        size_error_ = "declares a grey image of pixel depth " + std::to_string(f[4]) +
                      ", which MRPT does not define, at byte " + std::to_string(at + 16);
        throw RawlogSizeError(size_error_);
    }
    const uint64_t fields = 16 + (v >= 9 ? 4 : 0) + (v >= 5 ? 1 : 0);
    checkpoints_.push_back(pixelsAt(h, at, uint64_t{static_cast<uint32_t>(f[0])} * static_cast<uint32_t>(f[1]),
                                    v >= 9 ? pixelDepthBytes(f[4]) : 1, fields, "pixels of a grey image"));
    // Raw rows follow unless compressed (v3-4 above 16 KiB, or the v5+ flag): MRPT
    // refuses compressed ones.
    uint8_t zip = 0;
    if (v >= 5 && !peek(at + fields - 1, &zip, 1)) return 0;
    const bool raw = v == 2 || (v == 4 && static_cast<uint32_t>(f[3]) <= 16 * 1024) || (v >= 5 && !zip);
    return raw ? at + fields + static_cast<uint32_t>(f[3]) : 0;
}

uint64_t GuardedRawlogStream::armRawImage(const ObjectHeader& h)
{
    // v0: width, height, channels (uint32), origin (a byte), the data length (uint32), the
    // data. MRPT sizes the image from the first three, then reads the declared length
    // into it: a length beyond the image would write past its buffer.
    std::array<uint32_t, 3> f{};
    uint32_t length = 0;
    if (!peek(h.data, f.data(), 12) || !peek(h.data + 13, &length, 4)) return 0;
    const uint64_t pixels = uint64_t{f[0]} * f[1];
    // MRPT casts the channel count to a byte, and OpenCV reads 0 channels as 512.
    const uint64_t channels = (f[2] & 0xFF) != 0 ? (f[2] & 0xFF) : 512;
    if (pixels <= std::numeric_limits<uint64_t>::max() / channels && length > pixels * channels)
    {
        size_error_ = "declares an image of " + std::to_string(f[0]) + " x " + std::to_string(f[1]) + " x " +
                      std::to_string(channels) + " bytes and " + std::to_string(length) +
                      " bytes of data for it at byte " + std::to_string(h.data);
        throw RawlogSizeError(size_error_);
    }
    checkpoints_.push_back(pixelsAt(h, h.data, pixels, channels, 17, "pixels of an old-format image"));
    return h.data + 17 + length;
}

uint64_t GuardedRawlogStream::armJpeg(const ObjectHeader& h, uint64_t at)
{
    // The JPEG's byte count, then its bytes (MRPT copies them into a buffer first).
    // Returns where they end (0 if the count cannot be read).
    checkpoints_.push_back(countAt(h, at, 1, 0, "bytes of JPEG data"));
    uint32_t n = 0;
    std::array<uint8_t, 4> b{};
    if (!peek(at, &n, 4)) return 0;
    const uint64_t end = at + 4 + n;
    // Decoded once the size its frame header declares is known to be within the cap.
    const auto decoded = [&] { checkJpegDecodes(at, n); return end; };
    if (!peek(at + 4, b.data(), 2, kJpegWindow) || b[0] != 0xFF || b[1] != 0xD8) return decoded();
    // The frame header (SOF0-15 but DHT, JPG, DAC) gives the size the JPEG decodes to:
    // walk the marker segments up to it, at most 64 of them.
    uint64_t p = at + 6;
    for (int k = 0; k < 64 && p + 4 <= end && peek(p, b.data(), 4, kJpegWindow) && b[0] == 0xFF; ++k)
    {
        const uint8_t m = b[1];
        if (m == 0xD9 || m == 0xDA) return decoded();  // end of image, start of scan: no frame header
        if (m == 0xFF)
        {
            ++p;  // fill byte
            continue;
        }
        if (m == 0x01 || (m >= 0xD0 && m <= 0xD7))
        {
            p += 2;  // markers without a segment
            continue;
        }
        const bool frame = m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC;
        std::array<uint8_t, 6> sof{};  // precision, height, width, components
        if (frame && peek(p + 4, sof.data(), 6, kJpegWindow))
        {
            const uint64_t bytes = bigEndian16(&sof[1]) * bigEndian16(&sof[3]) * std::max<uint64_t>(sof[5], 1);
            if (bytes <= kMaxDecodedImageBytes) return decoded();
            size_error_ = "holds a JPEG image of " + std::to_string(bigEndian16(&sof[3])) + " x " +
                          std::to_string(bigEndian16(&sof[1])) + " x " + std::to_string(sof[5]) +
                          " bytes decoded at byte " + std::to_string(at) + ", more than the " +
                          std::to_string(kMaxDecodedImageBytes) + " a rawlog image may decode to";
            throw RawlogSizeError(size_error_);
        }
        p += 2 + bigEndian16(&b[2]);
    }
    return decoded();
}

}  // namespace hymm::io::detail
