#include "GuardedRawlogStream.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstring>

namespace hymm::io::detail
{
namespace
{
constexpr size_t kChunk = 1 << 16;
// MRPT writes an object as: 0x80 | name length, the name, a version byte, the data, 0x88.
constexpr uint8_t kEndFlag = 0x88;
// Smallest serialised object (a null pointer: header, "nullptr", end flag).
constexpr uint64_t kMinObjectBytes = 9;
// The most bytes the stream reads ahead to find where an object's counts lie.
constexpr uint64_t kMaxPeek = 4096;

gzFile asGz(void* p) { return static_cast<gzFile>(p); }

// "mrpt::obs::CSensoryFrame" (MRPT 2) and "CSensoryFrame" (older rawlogs) alike.
std::string unqualified(const std::string& name)
{
    const auto colon = name.rfind("::");
    return colon == std::string::npos ? name : name.substr(colon + 2);
}

std::string gzErrorText(gzFile f)
{
    int code = Z_OK;
    const char* msg = gzerror(f, &code);
    if (code == Z_OK) return {};
    return msg && *msg ? msg : "zlib error " + std::to_string(code);
}
}  // namespace

GuardedRawlogStream::GuardedRawlogStream(const std::string& path) : path_(path)
{
    gz_ = gzopen(path.c_str(), "rb");
    if (!gz_) throw std::runtime_error("cannot open rawlog '" + path + "'");
    gzbuffer(asGz(gz_), 1 << 17);
    // Count the uncompressed bytes once: every declared size is checked against them.
    std::vector<uint8_t> buf(kChunk);
    for (;;)
    {
        const int n = gzread(asGz(gz_), buf.data(), static_cast<unsigned>(buf.size()));
        if (n > 0) total_ += static_cast<uint64_t>(n);
        if (n <= 0 || static_cast<size_t>(n) < buf.size())
        {
            data_error_ = gzErrorText(asGz(gz_));
            if (n < 0 && data_error_.empty()) data_error_ = "read error";
            break;
        }
    }
    // Reopened rather than rewound: zlib refuses to rewind after a data error.
    gzclose(asGz(gz_));
    gz_ = gzopen(path.c_str(), "rb");
    if (!gz_) throw std::runtime_error("cannot reopen rawlog '" + path + "'");
    gzbuffer(asGz(gz_), 1 << 17);
}

GuardedRawlogStream::~GuardedRawlogStream()
{
    if (gz_) gzclose(asGz(gz_));
}

size_t GuardedRawlogStream::rawRead(void* buffer, size_t count)
{
    count = static_cast<size_t>(std::min<uint64_t>(count, total_ - pos_));
    auto* out = static_cast<uint8_t*>(buffer);
    size_t done = std::min(count, ahead_.size());
    std::copy_n(ahead_.begin(), done, out);
    ahead_.erase(ahead_.begin(), ahead_.begin() + static_cast<std::ptrdiff_t>(done));
    while (done < count)
    {
        const size_t want = std::min<size_t>(count - done, 1u << 30);
        const int n = gzread(asGz(gz_), out + done, static_cast<unsigned>(want));
        if (n <= 0) break;
        done += static_cast<size_t>(n);
    }
    pos_ += done;
    return done;
}

bool GuardedRawlogStream::peek(uint64_t offset, void* out, size_t n)
{
    if (offset < pos_ || offset + n > total_ || offset + n - pos_ > kMaxPeek) return false;
    const size_t need = static_cast<size_t>(offset + n - pos_);
    while (ahead_.size() < need)
    {
        std::array<uint8_t, 1024> tmp{};
        const size_t want = std::min(tmp.size(), need - ahead_.size());
        const int got = gzread(asGz(gz_), tmp.data(), static_cast<unsigned>(want));
        if (got <= 0) return false;
        ahead_.insert(ahead_.end(), tmp.begin(), tmp.begin() + got);
    }
    std::memcpy(out, ahead_.data() + (offset - pos_), n);
    return true;
}

uint64_t GuardedRawlogStream::skipPose3D(uint64_t at)
{
    // MRPT 2 writes "mrpt::poses::CPose3D", older versions "CPose3D".
    uint8_t len = 0;
    if (!peek(at, &len, 1) || !(len & 0x80)) return 0;
    len &= 0x7F;
    std::array<char, 32> name{};
    if (len > name.size() || !peek(at + 1, name.data(), len)) return 0;
    if (unqualified(std::string(name.data(), len)) != "CPose3D") return 0;
    uint8_t version = 0;
    if (!peek(at + 1 + len, &version, 1)) return 0;
    // v2: x y z and a quaternion (7 doubles); v3: x y z and the rotation matrix (12).
    const uint64_t body = version == 2 ? 7 * 8 : version == 3 ? 12 * 8 : 0;
    if (body == 0) return 0;
    const uint64_t end = at + 1 + len + 1 + body;
    uint8_t flag = 0;
    if (!peek(end, &flag, 1) || flag != kEndFlag) return 0;
    return end + 1;
}

void GuardedRawlogStream::armFor(const std::string& qualified)
{
    const std::string name = unqualified(qualified);
    // pos_ is just past the class name: the version byte comes next.
    uint8_t v = 0;
    if (!peek(pos_, &v, 1)) return;
    const uint64_t data = pos_ + 1;
    if (name == "CSensoryFrame" && v <= 2)
    {
        // v0: ID (uint32) and a timestamp (uint64) before the count; v1: the ID.
        const uint64_t at = data + (v == 0 ? 12 : v == 1 ? 4 : 0);
        checkpoints_.push_back({at, kMinObjectBytes, 1, "observations"});
    }
    else if (name == "CActionCollection" && v == 0)
        checkpoints_.push_back({data, kMinObjectBytes, 1, "actions"});
    else if (name == "CObservation2DRangeScan" && (v == 6 || v == 7))
    {
        // aperture (float), rightToLeft (bool), maxRange (float), sensorPose (CPose3D).
        const uint64_t at = skipPose3D(data + 9);
        if (at == 0) return;
        // Per beam a float range and a validity byte; then stdError (float), timestamp
        // (uint64), beamAperture (float), the label's length, deltaPitch (float),
        // hasIntensity (v7) and the end flag. MRPT allocates 9 bytes per beam.
        Checkpoint c{at, 5, 4 + 8 + 4 + 4 + 4 + (v >= 7 ? 1u : 0u) + 1, "beams"};
        c.scan_beams = true;
        c.scan_version = v;
        checkpoints_.push_back(c);
    }
    else if (name == "CObservationBearingRange" && v <= 3)
    {
        // min/max distance (floats), field of view (2 floats from v3, 1 before),
        // sensorLocationOnRobot (CPose3D), timestamp (v2+), validCovariances (v3+, then
        // three floats when false), then the count; each measurement range, yaw, pitch
        // (floats) and the landmark ID (int32), then the label (v1+) and the end flag.
        uint64_t at = skipPose3D(data + 8 + (v >= 3 ? 8 : 4));
        if (at == 0) return;
        if (v >= 2) at += 8;
        if (v >= 3)
        {
            uint8_t valid_cov = 0;
            if (!peek(at, &valid_cov, 1)) return;
            at += 1 + (valid_cov ? 0 : 12);
        }
        checkpoints_.push_back({at, 16, (v >= 1 ? 4u : 0u) + 1, "measurements"});
    }
}

void GuardedRawlogStream::checkCount(const Checkpoint& c)
{
    uint32_t n = 0;
    if (!peek(c.offset, &n, sizeof(n))) return;  // a short read: MRPT reports it
    const uint64_t left = total_ - (c.offset + sizeof(n));
    const uint64_t need = static_cast<uint64_t>(n) * c.element_bytes + c.tail_bytes;
    if (need > left)
    {
        size_error_ = "declares " + std::to_string(n) + " " + c.what + " (at least " +
                      std::to_string(need) + " bytes) at byte " + std::to_string(c.offset) +
                      " but only " + std::to_string(left) + " bytes follow in the file";
        throw RawlogSizeError(size_error_);
    }
    if (c.scan_beams)
    {
        // The sensor label's length follows the beams, stdError, timestamp, beamAperture.
        const uint64_t label = c.offset + sizeof(n) + 5ull * n + 16;
        checkpoints_.push_back({label, 1, 4 + (c.scan_version >= 7 ? 1u : 0u) + 1,
                                "bytes of sensor label"});
    }
}

size_t GuardedRawlogStream::Read(void* buffer, size_t count)
{
    if (count == 0) return 0;
    if (!checkpoints_.empty())
    {
        // Counts are read with a single 4-byte read at the offset found when the
        // object's class name went by; anything else means the layout was not the one
        // expected, and the checkpoint is dropped unchecked.
        std::vector<Checkpoint> due;
        auto it = std::remove_if(checkpoints_.begin(), checkpoints_.end(),
                                 [&](const Checkpoint& c)
                                 {
                                     if (c.offset > pos_) return false;
                                     if (c.offset == pos_ && count == 4) due.push_back(c);
                                     return true;
                                 });
        checkpoints_.erase(it, checkpoints_.end());
        for (const auto& c : due) checkCount(c);
    }
    const size_t n = rawRead(buffer, count);
    const auto* bytes = static_cast<const uint8_t*>(buffer);
    if (n == 1)
    {
        last_read_byte_ = bytes[0];
        return n;
    }
    // A class name: read right after its length byte (0x80 | length).
    if (last_read_byte_ >= 0 && n == count && (last_read_byte_ & 0x80) &&
        static_cast<size_t>(last_read_byte_ & 0x7F) == n)
    {
        const std::string name(reinterpret_cast<const char*>(bytes), n);
        armFor(name);
    }
    last_read_byte_ = -1;
    return n;
}

size_t GuardedRawlogStream::Write(const void*, size_t)
{
    throw std::logic_error("rawlog '" + path_ + "' is opened for reading");
}

uint64_t GuardedRawlogStream::Seek(int64_t offset, TSeekOrigin origin)
{
    const uint64_t target = origin == sFromBeginning ? static_cast<uint64_t>(offset)
                            : origin == sFromCurrent ? pos_ + static_cast<uint64_t>(offset)
                                                     : total_ + static_cast<uint64_t>(offset);
    if (target < pos_ || target > total_)
        throw std::logic_error("rawlog '" + path_ + "': only forward seeks are supported");
    std::vector<uint8_t> skip(kChunk);
    while (pos_ < target)
        if (rawRead(skip.data(), static_cast<size_t>(std::min<uint64_t>(kChunk, target - pos_))) == 0)
            break;
    return pos_;
}

}  // namespace hymm::io::detail
