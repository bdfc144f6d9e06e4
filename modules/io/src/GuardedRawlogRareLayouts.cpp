// GuardedRawlogStream: the counts and labels of the rarer MRPT observation classes that
// MRPT builds inside sensory frames (rotating lidars, reflectivity, wireless power, wind,
// robot pose, skeleton, CAN bus, RFID, raw DAQ, gas sensors, 6-D features, RGB-D 360, point
// clouds) and the messages of a GPS observation. Offsets follow MRPT 2.5's serializeFrom()
// of each class.
#include "GuardedRawlogStream.h"

#include <mrpt/obs/gnss_messages_novatel.h>
#include <mrpt/obs/gnss_messages_type_list.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>

namespace hymm::io::detail
{
namespace
{
// How far ahead the walks of a GPS observation's messages and of an RFID count's text may
// look (the 4 KiB of peek() cut them short).
constexpr uint64_t kWalkWindow = 16u << 20;
// Smallest serialised 6x6 CMatrixD object: header (length byte, a name of at least one
// byte, version), rows and columns, 36 doubles, end flag.
constexpr uint64_t kMin66MatrixBytes = 1 + 1 + 1 + 8 + 36 * 8 + 1;
}  // namespace

bool GuardedRawlogStream::armRare(const ObjectHeader& h)
{
    const std::string& name = h.name;
    const int v = h.version;
    const uint64_t data = h.data;
    const char* label = "bytes of sensor label";
    if (name == "CObservationRotatingScan" && v == 0)
        armRotatingScan(h);
    else if (name == "CObservationReflectivity" && v <= 1)
    {
        // The level (float), the channel (int16, v1), the sensor pose, label, timestamp.
        const uint64_t at = skipObject(data + 4 + (v >= 1 ? 2 : 0));
        if (at != 0) checkpoints_.push_back(countAt(h, at, 1, 8, label));
    }
    else if ((name == "CObservationWirelessPower" || name == "CObservationWindSensor") && v >= 1 && v <= 3)
        // The power, or speed and direction (doubles); label, timestamp (v2+), pose (v3).
        checkpoints_.push_back(countAt(h, data + (name == "CObservationWindSensor" ? 16 : 8), 1,
                                       (v >= 2 ? 8 : 0) + (v >= 3 ? kMinPose3DBytes : 0), label));
    else if (name == "CObservationRobotPose" && v <= 1)
    {
        // The pose (a CPose3DPDFGaussian object), label, timestamp, sensor pose (v1).
        const uint64_t at = skipObject(data);
        if (at != 0) checkpoints_.push_back(countAt(h, at, 1, 8 + (v >= 1 ? kMinPose3DBytes : 0), label));
    }
    else if (name == "CObservationSkeleton" && v <= 2)
        // 15 joints of x, y, z and a confidence (doubles), label, timestamp, sensor pose (v2).
        checkpoints_.push_back(countAt(h, data + 15 * 32, 1, 8 + (v >= 2 ? kMinPose3DBytes : 0), label));
    else if (name == "CObservationCANBusJ1939" && v <= 1)
    {
        // PGN (uint16) and five bytes, the data bytes, the raw frame's bytes (one read
        // each), label, timestamp.
        checkpoints_.push_back(countAt(h, data + 7, 1, 4 + 4 + 8, "CAN data bytes"));
        checkpoints_.back().then = {{{"CAN raw frame bytes", 0, 1, 4 + 8 + endFlagBytes(h)},
                                     {label, 0, 1, 8 + endFlagBytes(h)}}};
    }
    else if (name == "CObservationRFID" && v <= 4)
        armRfid(h);
    else if (name == "CObservationRawDAQ" && v == 0)
        armRawDaq(h);
    else if (name == "CObservationGasSensors" && v <= 5)
        armGasSensors(h);
    else if (name == "CObservationRGBD360" && v == 1)
        armRgbd360(h);
    else if (name == "CObservation6DFeatures" && v == 0)
    {
        // Two floats, the sensor pose; per feature a CPose3D object, an int32 ID and a 6x6
        // information matrix (a CMatrixD object); then label, timestamp.
        const uint64_t at = skipObject(data + 8);
        if (at != 0)
            checkpoints_.push_back(
                countAt(h, at, kMinPose3DBytes + 4 + kMin66MatrixBytes, 4 + 8, "6-D features"));
    }
    else
        return false;
    return true;
}

void GuardedRawlogStream::armGasSensors(const ObjectHeader& h)
{
    const int v = h.version;
    if (v <= 1)
        // Sixteen voltages of a 2006 e-nose as a float vector; MRPT sizes the vector from
        // its count before it asserts the count is 16.
        checkpoints_.push_back(countAt(h, h.data, 4, 0, "gas sensor voltages"));
    else
        // Per reading: the e-nose pose (a CPose3D object), the voltages (float vector) and
        // sensor types (int vector), a temperature flag (v3+); then label (v4+), timestamp
        // (v5). MRPT holds about 104 B per reading.
        checkpoints_.push_back(countAt(h, h.data, kMinPose3DBytes + 4 + 4 + (v >= 3 ? 1 : 0),
                                       (v >= 4 ? 4 : 0) + (v >= 5 ? 8 : 0), "gas sensor readings"));
}

void GuardedRawlogStream::armRgbd360(const ObjectHeader& h)
{
    // The maximum range (a float), the sensor pose (a CPose3D object), a flag; if set, two
    // range images of rows x columns uint16 (MRPT sizes each from its two dimensions),
    // one after the other. At least 43 bytes follow them: the intensity flag, two
    // timestamps, the error (a float), the timestamp, the label, two external-storage
    // flags and file names.
    const uint64_t at = skipObject(h.data + 4);
    uint8_t has_range = 0;
    if (at == 0 || !peek(at, &has_range, 1) || !has_range) return;
    Checkpoint c = countAt(h, at + 1, 2, 8 + 43, "range image pixels");
    c.kind = Checkpoint::Matrix;
    c.then[0] = {"range image pixels", 0, 2, 43 + endFlagBytes(h), true};
    checkpoints_.push_back(c);
}

void GuardedRawlogStream::armPointCloud(const ObjectHeader& h)
{
    // The label, the timestamp, the sensor pose, the storage format (a byte); then the
    // external file's name, or the cloud: an object MRPT reads through a points-map
    // pointer (any registered class is built first, then cast), which must be a points
    // map or null. Its point count: armSensor (CSimplePointsMap, ...).
    checkpoints_.push_back(countAt(h, h.data, 1, 8 + kMinPose3DBytes + 1, "bytes of sensor label"));
    uint32_t label = 0;
    uint8_t external = 0;
    if (!peek(h.data, &label, 4) || label > total_) return;
    const uint64_t at = skipObject(h.data + 4 + label + 8);
    if (at == 0 || !peek(at, &external, 1)) return;
    if (external)
    {
        checkpoints_.push_back(countAt(h, at + 1, 1, 0, "bytes of point cloud file name"));
        return;
    }
    const std::string cls = classAt(at + 1);
    const auto* points_map = mrpt::rtti::findRegisteredClass("mrpt::maps::CPointsMap");
    if (!cls.empty() && cls != "nullptr" && points_map)
        requireClass(cls, points_map, at + 1, "the cloud of a CObservationPointCloud");
}

void GuardedRawlogStream::armRawDaq(const ObjectHeader& h)
{
    // The label, the timestamp and sample rate (8 B each), then 13 vectors (count, then
    // elements of 1, 2, 4 or 8 B) with the channel count (uint16) and the interleaving
    // flag between the 5th and the 6th.
    static constexpr std::array<uint64_t, 13> kElement{1, 2, 4, 4, 8, 1, 2, 4, 8, 1, 1, 4, 8};
    // Named as MRPT's fields, so an error says which vector declared too much.
    static constexpr std::array<const char*, 13> kName{
        "DAQ samples of AIN_8bits",   "DAQ samples of AIN_16bits",   "DAQ samples of AIN_32bits",
        "DAQ samples of AIN_float",   "DAQ samples of AIN_double",   "DAQ samples of AOUT_8bits",
        "DAQ samples of AOUT_16bits", "DAQ samples of AOUT_float",   "DAQ samples of AOUT_double",
        "DAQ samples of DIN",         "DAQ samples of DOUT",         "DAQ samples of CNTRIN_32bits",
        "DAQ samples of CNTRIN_double"};
    const uint64_t end = endFlagBytes(h);
    Checkpoint c = countAt(h, h.data, 1, 16 + 13 * 4 + 3, "bytes of sensor label");
    for (size_t i = 0; i < kElement.size(); ++i)
    {
        const uint64_t later = (kElement.size() - 1 - i) * 4 + (i < 5 ? 3 : 0);
        c.then[i] = {kName[i], i == 0 ? 16u : i == 5 ? 3u : 0u, kElement[i], later + end};
    }
    checkpoints_.push_back(c);
}

void GuardedRawlogStream::armRfid(const ObjectHeader& h)
{
    // Per tag: the power (double), the EPC and the antenna port (strings); MRPT holds
    // about 72 B per tag. v4 stores the tag count as a uint32, older versions as decimal
    // text that MRPT parses with atoi() before sizing the tags.
    constexpr uint64_t kTagBytes = 8 + 4 + 4;
    const int v = h.version;
    const uint64_t tail = (v >= 1 ? 4 : 0) + (v >= 2 ? 8 : 0) + (v >= 3 ? kMinPose3DBytes : 0);
    if (v == 4)
    {
        checkpoints_.push_back(countAt(h, h.data, kTagBytes, tail, "RFID tags"));
        return;
    }
    checkpoints_.push_back(countAt(h, h.data, 1, 0, "bytes of the RFID tag count"));
    uint32_t len = 0;
    if (!peek(h.data, &len, 4)) return;
    // atoi stops at the first non-digit and saturates long before 4 KiB of digits.
    std::string text(std::min<uint32_t>(len, 4096), '\0');
    if (!peek(h.data + 4, text.data(), text.size(), kWalkWindow)) return;
    // As MRPT reads it: glibc's atoi is (int) strtol, and the result goes into a uint32
    // ("-1" is 4294967295 tags).
    const auto n = static_cast<uint32_t>(static_cast<int>(std::strtol(text.c_str(), nullptr, 10)));
    const uint64_t left = total_ - std::min(total_, h.data + 4 + len);
    if (uint64_t{n} * kTagBytes + tail <= left) return;
    size_error_ = "declares " + std::to_string(n) + " RFID tags (at least " +
                  std::to_string(uint64_t{n} * kTagBytes + tail) + " bytes) at byte " +
                  std::to_string(h.data) + " but only " + std::to_string(left) + " bytes follow in the file";
    throw RawlogSizeError(size_error_);
}

void GuardedRawlogStream::armRotatingScan(const ObjectHeader& h)
{
    // The timestamp, the label, row and column counts (uint16), four doubles, the lidar
    // model (a string), minimum and maximum range (doubles), the sensor pose, the
    // original timestamp, a flag; then the range image's columns and rows (uint16; MRPT
    // sizes it, 2 B per pixel, and reads it), the intensity image's (1 B per pixel), and
    // the other layers (each the range image's size, read before the next one is sized).
    checkpoints_.push_back(countAt(h, h.data + 8, 1, 4 + 32 + 4, "bytes of sensor label"));
    uint32_t label = 0, model = 0;
    if (!peek(h.data + 8, &label, 4) || label > total_) return;
    const uint64_t model_at = h.data + 12 + label + 4 + 32;
    checkpoints_.push_back(countAt(h, model_at, 1, 16 + kMinPose3DBytes + 9 + 4, "bytes of lidar model"));
    if (!peek(model_at, &model, 4) || model > total_) return;
    const uint64_t pose = skipObject(model_at + 4 + model + 16);
    if (pose == 0) return;
    const uint64_t dims = pose + 9;
    std::array<uint16_t, 2> range{}, intensity{};  // columns, rows
    if (!peek(dims, range.data(), 4)) return;
    const uint64_t pixels = uint64_t{range[0]} * range[1];
    // Columns and rows are uint16 reads: the check fires on a 2-byte read.
    checkpoints_.push_back(pixelsAt(h, dims, pixels, 2, 4 + 4 + 2, "range image pixels", 2));
    if (!peek(dims + 4 + 2 * pixels, intensity.data(), 4)) return;
    checkpoints_.push_back(pixelsAt(h, dims + 4 + 2 * pixels, uint64_t{intensity[0]} * intensity[1], 1, 4 + 2,
                                    "intensity image pixels", 2));
}

void GuardedRawlogStream::armGpsMessages(const ObjectHeader& h)
{
    // v10-11: two timestamps, the label, the sensor pose (a CPose3D object), a flag (v11),
    // the message count, then each message: its type (int32) and its content. MRPT
    // creates each message with new and reads it (a failed read leaks it: lsan.supp).
    // Most types are a fixed block behind its byte count (MRPT checks the count before
    // reading); the NovAtel generic frames size their body from a count and then read 4
    // bytes into it whatever its size (a heap overflow below 4, and MRPT's own position
    // afterwards); RANGECMP and VERSION hold at most 2,000 records (MRPT asserts it); the
    // Topcon messages have no byte count (armTopcon). The walk follows MRPT's reads and
    // stops at an unknown type or after 1,000 messages.
    using namespace mrpt::obs::gnss;
    uint32_t label = 0, count = 0;
    if (!peek(h.data + 16, &label, 4, kWalkWindow) || label > total_) return;
    uint64_t p = skipObject(h.data + 20 + label);
    if (p == 0) return;
    p += h.version >= 11 ? 1 : 0;
    if (!peek(p, &count, 4, kWalkWindow)) return;
    p += 4;
    for (uint32_t i = 0; i < std::min<uint32_t>(count, 1000); ++i)
    {
        int32_t type = 0;
        uint32_t n = 0;
        if (!peek(p, &type, 4, kWalkWindow)) return;
        p += 4;
        if (type == NV_OEM6_GENERIC_FRAME || type == NV_OEM6_GENERIC_SHORT_FRAME)
        {
            p += type == NV_OEM6_GENERIC_FRAME ? sizeof(nv_oem6_header_t) : sizeof(nv_oem6_short_header_t);
            if (!peek(p, &n, 4, kWalkWindow)) return;
            if (n > 0 && n < 4)
            {
                size_error_ = "holds a NovAtel frame of " + std::to_string(n) + " bytes at byte " +
                              std::to_string(p) + ", into which MRPT reads 4";
                throw RawlogSizeError(size_error_);
            }
            checkpoints_.push_back(countAt(h, p, 1, 0, "bytes of a NovAtel frame"));
            p += 4 + (n > 0 ? 4 : 0);
            continue;
        }
        if (type == NV_OEM6_RANGECMP || type == NV_OEM6_VERSION)
        {
            const uint64_t record = type == NV_OEM6_RANGECMP ? sizeof(Message_NV_OEM6_RANGECMP::TCompressedRangeLog)
                                                             : sizeof(Message_NV_OEM6_VERSION::TComponentVersion);
            p += 4 + sizeof(nv_oem6_header_t);
            if (!peek(p, &n, 4, kWalkWindow) || n >= 2000) return;
            p += 4 + n * record;
            continue;
        }
        if (type == TOPCON_PZS || type == TOPCON_SATS)
        {
            p = armTopcon(h, type == TOPCON_SATS, p);
            if (p == 0) return;
            continue;
        }
        if (!peek(p, &n, 4, kWalkWindow)) return;
        std::unique_ptr<gnss_message> known(gnss_message::Factory(static_cast<gnss_message_type_t>(type)));
        if (!known) return;  // MRPT refuses an unknown type
        p += 4 + uint64_t{n};
    }
}

uint64_t GuardedRawlogStream::armTopcon(const ObjectHeader& h, bool sats, uint64_t p)
{
    if (!sats)
    {
        // PZS: 4 doubles, a float, a double, 5 bytes, a flag, 6 doubles, a flag, the
        // position covariance (a CMatrixF object, checked as MRPT reads it), a flag, the
        // velocity covariance, a flag and 3 bytes.
        p = skipObject(p + 32 + 4 + 8 + 5 + 1 + 48 + 1, kWalkWindow);
        if (p != 0) p = skipObject(p + 1, kWalkWindow);
        return p == 0 ? 0 : p + 1 + 3;
    }
    // SATS: the satellites' IDs and elevations (bytes) and azimuths (int16), each a
    // counted vector that MRPT sizes before reading it.
    Checkpoint c = countAt(h, p, 1, 4 + 4, "Topcon satellite IDs");
    c.then[0] = {"Topcon satellite elevations", 0, 1, 4 + endFlagBytes(h)};
    c.then[1] = {"Topcon satellite azimuths", 0, 2, endFlagBytes(h)};
    checkpoints_.push_back(c);
    for (const uint64_t element : {1, 1, 2})
    {
        uint32_t n = 0;
        if (!peek(p, &n, 4, kWalkWindow)) return 0;
        p += 4 + n * element;
    }
    return p;
}

}  // namespace hymm::io::detail
