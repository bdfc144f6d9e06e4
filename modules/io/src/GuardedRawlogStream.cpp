#include "GuardedRawlogStream.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>

namespace hymm::io::detail
{
namespace
{
constexpr size_t kChunk = 1 << 16;

// n elements of `element` bytes and `tail` bytes more, saturated: rows x columns of a
// matrix reach 2^64, and a product that wrapped round would pass as small.
uint64_t bytesFor(uint64_t n, uint64_t element, uint64_t tail)
{
    const uint64_t max = std::numeric_limits<uint64_t>::max();
    if (element != 0 && n > (max - tail) / element) return max;
    return n * element + tail;
}
gzFile asGz(void* p) { return static_cast<gzFile>(p); }

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
    // Consumed look-ahead bytes are dropped in bulk: erasing them at every read shifted
    // the whole window (up to 64 MiB for a JPEG) once per read.
    size_t done = std::min(count, ahead_.size() - ahead_head_);
    std::copy_n(ahead_.begin() + static_cast<std::ptrdiff_t>(ahead_head_), done, out);
    ahead_head_ += done;
    if (ahead_head_ == ahead_.size())
    {
        ahead_.clear();
        ahead_head_ = 0;
    }
    else if (ahead_head_ > (64u << 10) && 2 * ahead_head_ > ahead_.size())
    {
        ahead_.erase(ahead_.begin(), ahead_.begin() + static_cast<std::ptrdiff_t>(ahead_head_));
        ahead_head_ = 0;
    }
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

bool GuardedRawlogStream::peek(uint64_t offset, void* out, size_t n) { return peek(offset, out, n, kMaxPeek); }

bool GuardedRawlogStream::peek(uint64_t offset, void* out, size_t n, uint64_t max_ahead)
{
    const uint8_t* at = lookAhead(offset, n, max_ahead);
    if (!at) return false;
    std::memcpy(out, at, n);
    return true;
}

const uint8_t* GuardedRawlogStream::lookAhead(uint64_t offset, size_t n, uint64_t max_ahead)
{
    if (offset < pos_ || offset + n > total_ || offset + n - pos_ > max_ahead) return nullptr;
    const size_t need = static_cast<size_t>(offset + n - pos_);
    const size_t have = ahead_.size() - ahead_head_;
    if (have < need)
    {
        // One gzread for what is missing: a JPEG's look-ahead of up to 64 MiB took 65,000
        // calls in 1 KiB pieces.
        const size_t old = ahead_.size(), missing = need - have;
        ahead_.resize(old + missing);
        size_t filled = 0;
        while (filled < missing)
        {
            const size_t want = std::min<size_t>(missing - filled, 1u << 30);
            const int got = gzread(asGz(gz_), ahead_.data() + old + filled, static_cast<unsigned>(want));
            if (got <= 0)
            {
                ahead_.resize(old + filled);
                return nullptr;
            }
            filled += static_cast<size_t>(got);
        }
    }
    return ahead_.data() + ahead_head_ + (offset - pos_);
}

bool GuardedRawlogStream::peekHeader(uint64_t at, ObjectHeader& h, uint64_t max_ahead)
{
    // MRPT >= 0.5.5: 0x80 | name length, the name, a version byte ... end flag.
    // Older: the name length (< 0x80), three zero bytes, the name, an int32 version, and
    // no end flag.
    uint8_t len = 0;
    if (!peek(at, &len, 1, max_ahead)) return false;
    h.old_format = !(len & 0x80);
    len &= 0x7F;
    uint64_t name_at = at + 1;
    if (h.old_format)
    {
        std::array<uint8_t, 3> zeros{};
        if (!peek(at + 1, zeros.data(), 3, max_ahead) || zeros[0] || zeros[1] || zeros[2]) return false;
        name_at += 3;
    }
    std::array<char, 128> name{};
    if (len == 0 || len > 120 || !peek(name_at, name.data(), len, max_ahead)) return false;
    h.name = unqualified(classNameOf(reinterpret_cast<const uint8_t*>(name.data()), len));
    if (h.old_format)
    {
        int32_t v = 0;
        if (!peek(name_at + len, &v, 4, max_ahead) || v < 0 || v > 255) return false;
        h.version = v;
        h.data = name_at + len + 4;
    }
    else
    {
        uint8_t v = 0;
        if (!peek(name_at + len, &v, 1, max_ahead)) return false;
        h.version = v;
        h.data = name_at + len + 1;
    }
    return true;
}

uint64_t GuardedRawlogStream::skipObject(uint64_t at, uint64_t max_ahead)
{
    ObjectHeader h;
    return peekHeader(at, h, max_ahead) ? objectEnd(h, max_ahead) : 0;
}

uint64_t GuardedRawlogStream::objectEnd(const ObjectHeader& h, uint64_t max_ahead)
{
    uint64_t end = 0;
    if (h.name == "CPose3D")
    {
        // v0: a float 4x4 matrix object; v1: a double one; v2: x y z and a quaternion
        // (7 doubles); v3: x y z and the rotation matrix (12 doubles).
        if (h.version <= 1) end = skipObject(h.data, max_ahead);
        else if (h.version == 2) end = h.data + 7 * 8;
        else if (h.version == 3) end = h.data + 12 * 8;
    }
    else if (h.name == "CPose2D")
        end = h.version == 0 ? h.data + 3 * 4 : h.version == 1 ? h.data + 3 * 8 : 0;
    else if (h.name == "CPose3DQuat" && h.version == 0)
        end = h.data + 7 * 8;  // x y z and the quaternion
    else if (h.name == "TCamera" && h.version >= 4 && h.version <= 6)
    {
        // The focal length, 8 distortion and 4 intrinsic doubles, rows and columns, the
        // camera name (v5+), the distortion model (v6, a byte).
        end = h.data + 8 + 64 + 32 + 8;
        uint32_t name = 0;
        if (h.version >= 5 && (!peek(end, &name, 4, max_ahead) || name > total_)) return 0;
        if (h.version >= 5) end += 4 + name;
        if (h.version >= 6) end += 1;
    }
    else if (h.name == "CPose3DPDFGaussian" && h.version == 1)
    {
        // The mean (a CPose3D object), then the 21 doubles of the covariance's upper
        // triangle.
        end = skipObject(h.data, max_ahead);
        if (end != 0) end += 21 * 8;
    }
    else if (h.version == 0 && matrixElementBytes(h.name) != 0)
    {
        std::array<uint32_t, 2> rc{};
        if (!peek(h.data, rc.data(), 8, max_ahead)) return 0;
        const uint64_t bytes = bytesFor(uint64_t{rc[0]} * rc[1], matrixElementBytes(h.name), 8);
        if (bytes > total_) return 0;
        end = h.data + bytes;
    }
    if (end == 0) return 0;
    if (h.old_format) return end;
    uint8_t flag = 0;
    if (!peek(end, &flag, 1, max_ahead) || flag != kEndFlag) return 0;
    return end + 1;
}

void GuardedRawlogStream::refuse(uint64_t n, uint64_t need, const Checkpoint& c, uint64_t left,
                                 uint64_t reserved)
{
    size_error_ = "declares " + std::to_string(n) + " " + c.what + " (at least " +
                  std::to_string(need) + " bytes) at byte " + std::to_string(c.offset) +
                  " but only " + std::to_string(left) + " bytes follow in the file";
    if (reserved > 0)
        size_error_ += ", " + std::to_string(std::min(reserved, left)) +
                       " of them needed by the enclosing objects' remaining elements";
    throw RawlogSizeError(size_error_);
}

uint64_t GuardedRawlogStream::reservedAfter(uint64_t at)
{
    claims_.erase(std::remove_if(claims_.begin(), claims_.end(), [&](uint64_t end) { return end <= at; }),
                  claims_.end());
    uint64_t reserved = 0;
    for (const uint64_t end : claims_) reserved += end - at;
    return reserved;
}

void GuardedRawlogStream::checkCount(const Checkpoint& c)
{
    uint32_t n = 0;
    if (!peek(c.offset, &n, sizeof(n))) return;  // a short read: MRPT reports it
    if (c.kind == Checkpoint::Cap)
    {
        if (n > c.cap)
        {
            size_error_ = "declares " + std::to_string(n) + " " + c.what + " at byte " +
                          std::to_string(c.offset) + ", more than the " +
                          std::to_string(c.cap) + " a rawlog may ask for";
            throw RawlogSizeError(size_error_);
        }
        return;
    }
    if (c.kind == Checkpoint::Pixels)
    {
        // cap pixels of element_bytes each (a v0 image's channel count is a uint32 too),
        // and the fixed fields, all from the first dimension on.
        const uint64_t left = total_ - std::min(total_, c.offset);
        const uint64_t need = bytesFor(c.cap, c.element_bytes, c.tail_bytes);
        const uint64_t reserved = reservedAfter(c.offset);
        if (need > left || need + reserved > left) refuse(c.cap, need, c, left, reserved);
        return;
    }
    if (c.kind == Checkpoint::Matrix)
    {
        // Rows then columns, each read on its own; MRPT sizes the matrix after both.
        uint32_t cols = 0;
        if (!peek(c.offset + 4, &cols, sizeof(cols))) return;
        const uint64_t left = total_ - std::min(total_, c.offset + 8);
        const uint64_t elements = uint64_t{n} * cols;
        const uint64_t need = bytesFor(elements, c.element_bytes, c.tail_bytes);
        const uint64_t reserved = reservedAfter(c.offset + 8);
        if (need > left || need + reserved > left) refuse(elements, need, c, left, reserved);
        armNextInChain(c, c.offset + 8 + elements * c.element_bytes);
        return;
    }
    const uint64_t start = c.offset + sizeof(n);
    const uint64_t left = total_ - start;
    const uint64_t need = static_cast<uint64_t>(n) * c.element_bytes + c.tail_bytes;
    const uint64_t reserved = reservedAfter(start);
    if (need + reserved > left) refuse(n, need, c, left, reserved);
    if (n > 0) claims_.push_back(start + (uint64_t{n} - 1) * c.element_bytes);
    armNextInChain(c, start + uint64_t{n} * c.element_bytes);
}

void GuardedRawlogStream::armNextInChain(const Checkpoint& c, uint64_t elements_end)
{
    if (!c.then[0].what) return;
    // The next count of the chain follows the elements (and `gap` bytes more).
    Checkpoint s;
    s.offset = elements_end + c.then[0].gap;
    s.element_bytes = c.then[0].element;
    s.tail_bytes = c.then[0].tail;
    s.what = c.then[0].what;
    if (c.then[0].matrix) s.kind = Checkpoint::Matrix;
    std::copy(c.then.begin() + 1, c.then.end(), s.then.begin());
    checkpoints_.push_back(s);
}

size_t GuardedRawlogStream::Read(void* buffer, size_t count)
{
    if (count == 0) return 0;
    if (!checkpoints_.empty())
    {
        // Counts are read with a single read (4 bytes, 2 for a uint16) at the offset found
        // when the object's class name went by; anything else means the layout was not
        // the one expected, and the checkpoint is dropped unchecked.
        std::vector<Checkpoint> due;
        auto it = std::remove_if(checkpoints_.begin(), checkpoints_.end(),
                                 [&](const Checkpoint& c)
                                 {
                                     if (c.offset > pos_) return false;
                                     if (c.offset == pos_ && count == c.width) due.push_back(c);
                                     return true;
                                 });
        checkpoints_.erase(it, checkpoints_.end());
        for (const auto& c : due) checkCount(c);
    }
    const size_t n = rawRead(buffer, count);
    // MRPT's CArchive::ReadBuffer accepts a short read when at least one byte came, and
    // the value keeps whatever the rest of its bytes held: a 4-byte count cut by the end
    // of the file became billions of elements, sized before the next read failed. A read
    // the data cannot fill is refused whole, so MRPT sees the end of the file.
    if (n < count)
    {
        cut_read_ = cut_read_ || n > 0;
        return 0;
    }
    const auto* bytes = static_cast<const uint8_t*>(buffer);
    const int prev = last_read_byte_;
    const int old_len = old_header_len_;
    last_read_byte_ = n == 1 ? bytes[0] : -1;
    old_header_len_ = -1;
    if (trackFrames(count, n, bytes, prev)) return n;
    // Old-format header (before MRPT 0.5.5): a length byte below 0x80, three zero bytes.
    if (n == 3 && count == 3 && prev >= 1 && prev <= 120 && !bytes[0] && !bytes[1] && !bytes[2])
    {
        old_header_len_ = prev;
        return n;
    }
    // A class name: read right after its length byte (0x80 | length), or after the old
    // header's zeros.
    const bool new_name = prev >= 0 && (prev & 0x80) && static_cast<size_t>(prev & 0x7F) == n;
    const bool old_name = old_len > 0 && static_cast<size_t>(old_len) == n;
    if (n == count && (new_name || old_name))
    {
        const std::string name = classNameOf(bytes, n);
        trackHeader(name, old_name, pos_ - n - (old_name ? 4 : 1));
        armFor(name, old_name);
    }
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
