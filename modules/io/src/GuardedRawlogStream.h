/**
 * @file GuardedRawlogStream.h
 * @brief The byte stream RawlogReader hands to MRPT's deserialiser: a plain or gzip file
 *        read through zlib, which knows how many uncompressed bytes the file holds and
 *        refuses declared sizes that cannot fit in them.
 *
 * MRPT's serializeFrom() reads a count and resizes its containers before reading the
 * elements (CObservation2DRangeScan::resizeScan(N), CSensoryFrame's vector of N
 * observations, std::string lengths), so a rawlog declaring 0x10000000 beams makes it
 * allocate gigabytes, or crash when the allocation fails, before the short read is
 * noticed. This stream cannot see allocations, but it sees every read: when MRPT reads
 * the class name of one of the classes HYMM consumes, the stream peeks at the bytes that
 * follow (without consuming them), finds where that object's counts lie, and when MRPT
 * is about to read a count, checks count x (smallest serialised size of an element) +
 * the fixed fields after them against the bytes the file still holds. A count that does
 * not fit throws RawlogSizeError before MRPT sees it. The serialised element size is
 * chosen so that what MRPT then allocates stays below twice the remaining bytes.
 * Counts nest (a frame's observation holds a matrix; a crafted file nests collections in
 * collections, each declaring as many elements as the rest of the file could hold): the
 * bytes the enclosing counted containers still need for their remaining elements are not
 * available to a nested count, so what all the open levels allocate together stays
 * bounded by the file, not by its size times the nesting depth.
 *
 * The elements of a CActionCollection: MRPT reads each into a deep-copying pointer that
 * clones what it read without a null check, so an element that is a null object or an
 * object of another class (the cast to CAction gives null) was a segmentation fault
 * inside MRPT. The stream follows which objects are open (a header opens one, its end
 * flag closes it) and refuses such an element when its class name goes by (see open_).
 *
 * Guarded (MRPT 2.5 layouts, every version MRPT 2.5 still reads, old and current object
 * headers): the classes RawlogReader's users consume and the objects inside them --
 * CSensoryFrame and CActionCollection element counts; CObservation2DRangeScan beams and
 * label; CObservationBearingRange measurements and label; CObservationOdometry label;
 * CActionRobotMovement2D's motion-model sample count (a fixed cap); CActionRobotMovement3D's
 * velocity flags and velocities; CPosePDFParticles,
 * CPosePDFSOG and CPosePDFGrid element counts; CMatrixF/CMatrixD sizes (covariances,
 * old poses). Classes the pipeline does not read but MRPT builds inside frames
 * (GuardedRawlogSensorLayouts.cpp): comments, beacon ranges, ranges, IMUs, GPS labels and
 * messages, battery states, Velodyne, RGB-D and rotating scans, point clouds, every CImage
 * (decoded first if a JPEG: JpegCheck.cpp) and the rarer sensors
 * (GuardedRawlogRareLayouts.cpp). An entry must be an action collection, a frame or an
 * observation, a frame's element an observation (refused at the class name, before MRPT
 * builds it). Not guarded: the fields modules/io/README.md lists (e.g. an RGB-D scan's
 * label and layer names, a 3-D scene's objects): MRPT allocates what they declare.
 *
 * The file is decompressed once when opened to count its bytes (and to find corrupt gzip
 * data, so that it is reported as corrupt rather than as an early end).
 */
#pragma once

#include <mrpt/io/CStream.h>
#include <mrpt/rtti/CObject.h>

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace hymm::io::detail
{
// Bytes per element of MRPT's dynamic matrix classes (version 0: rows, columns, data);
// 0 for any other class. "CMatrix" is the float matrix of older rawlogs.
inline uint64_t matrixElementBytes(const std::string& name)
{
    if (name == "CMatrixF" || name == "CMatrix") return 4;
    if (name == "CMatrixD") return 8;
    return 0;
}

// MRPT writes an object as: 0x80 | name length, the name, a version byte, the data, 0x88.
inline constexpr uint8_t kEndFlag = 0x88;

// The class name MRPT looks up for a header's `n` name bytes: it copies them into a C
// string, so a zero byte ends the name (the version still follows all n bytes).
inline std::string classNameOf(const uint8_t* bytes, size_t n)
{
    size_t len = 0;
    while (len < n && bytes[len] != 0) ++len;
    return std::string(reinterpret_cast<const char*>(bytes), len);
}

// "mrpt::obs::CSensoryFrame" (MRPT 2) and "CSensoryFrame" (older rawlogs) alike.
inline std::string unqualified(const std::string& name)
{
    const auto colon = name.rfind("::");
    return colon == std::string::npos ? name : name.substr(colon + 2);
}

// What a CActionCollection's elements are, in the refusal of one that is not.
inline constexpr const char* kActionSlot = "an action of a CActionCollection";
inline constexpr const char* kObservationSlot = "an observation of a CSensoryFrame";

// A JPEG decodes to width x height x components bytes whatever its length in the file
// (MRPT sizes the image from the frame header; libjpeg holds up to twice that again for
// a progressive one). Cap on the decoded bytes of one image: an 8K x 8K colour image is
// 201 MB.
inline constexpr uint64_t kMaxDecodedImageBytes = uint64_t{1} << 28;
// Largest JPEG a rawlog may hold (it is decoded before MRPT decodes it:
// checkJpegDecodes), and how far ahead its bytes may be looked at.
inline constexpr uint32_t kMaxJpegBytes = 64u << 20;
inline constexpr uint64_t kJpegWindow = uint64_t{kMaxJpegBytes} + 4096;
// The most bytes the stream reads ahead by default to find where an object's counts lie.
inline constexpr uint64_t kMaxPeek = 4096;

// Smallest serialised object (a null pointer: header, "nullptr", end flag).
inline constexpr uint64_t kMinObjectBytes = 9;
// Smallest serialised CPose3D object: a length byte, the unqualified name, the version
// (2: x y z and a quaternion, 7 doubles) and the end flag.
inline constexpr uint64_t kMinPose3DBytes = 1 + 7 + 1 + 7 * 8 + 1;

/** Why libjpeg cannot decode the `n` bytes at `data` to at most `max_bytes` (JpegCheck.cpp);
 *  empty if it can. */
std::string jpegDecodeError(const uint8_t* data, size_t n, uint64_t max_bytes);

/** A declared size that does not fit in the rest of the file. */
struct RawlogSizeError : std::runtime_error
{
    using std::runtime_error::runtime_error;
};

class GuardedRawlogStream : public mrpt::io::CStream
{
public:
    /** Opens `path` and counts its uncompressed bytes; throws std::runtime_error if it
     *  cannot be opened. */
    explicit GuardedRawlogStream(const std::string& path);
    ~GuardedRawlogStream() override;
    GuardedRawlogStream(const GuardedRawlogStream&) = delete;
    GuardedRawlogStream& operator=(const GuardedRawlogStream&) = delete;

    size_t Read(void* buffer, size_t count) override;
    size_t Write(const void* buffer, size_t count) override;
    uint64_t Seek(int64_t offset, TSeekOrigin origin = sFromBeginning) override;
    uint64_t getTotalBytesCount() const override { return total_; }
    uint64_t getPosition() const override { return pos_; }

    /** Uncompressed bytes readable before the end or before corrupt data. */
    uint64_t readableBytes() const { return total_; }
    /** zlib's description of corrupt or truncated gzip data after readableBytes(); empty
     *  when the whole file decompressed cleanly. */
    const std::string& dataError() const { return data_error_; }
    /** The message of the last RawlogSizeError thrown (MRPT may wrap it). */
    const std::string& sizeError() const { return size_error_; }
    /** True once a read found some but not all of its bytes before the end of the data
     *  (refused whole: see Read). */
    bool cutRead() const { return cut_read_; }
    /** The next object read is a rawlog entry: its class must be an action collection, a
     *  sensory frame or an observation (refused at its class name, before MRPT builds
     *  it). */
    void beginEntry() { entry_start_ = pos_; }

private:
    /** At uncompressed offset `offset` MRPT reads a uint32 count of elements of at least
     *  `element_bytes` serialised bytes each, followed by at least `tail_bytes` more
     *  (Count); or rows and columns of a matrix (Matrix); or a count not backed by bytes
     *  in the file, which may not exceed `cap` (Cap); or the first dimension of an image
     *  of `cap` pixels of `element_bytes` each, whose `tail_bytes` of fixed fields and
     *  pixel data start at `offset` (Pixels: MRPT sizes the image from its header). */
    struct Checkpoint
    {
        enum Kind
        {
            Count,
            Matrix,
            Cap,
            Pixels
        };
        Kind kind = Count;
        uint64_t offset = 0;
        size_t width = 4;  // bytes of the read at `offset` that triggers the check
        uint64_t element_bytes = 0;
        uint64_t tail_bytes = 0;
        uint64_t cap = 0;
        const char* what = "";
        // Counts that follow this one, each `gap` bytes after the previous one's
        // elements, of elements of `element` bytes and `tail` bytes more (the sensor
        // labels of 2D scans and bearing-range observations; a 3-D movement's
        // velocities; an IMU's measurements and label). The first with no `what` ends
        // the chain.
        struct Next
        {
            const char* what = nullptr;
            uint64_t gap = 0;
            uint64_t element = 1;
            uint64_t tail = 0;
            bool matrix = false;  // rows and columns (Matrix), not a count
        };
        std::array<Next, 13> then{};
    };
    /** A serialised object's header as MRPT writes it (current or pre-0.5.5 format). */
    struct ObjectHeader
    {
        std::string name;  // without namespace
        int version = 0;
        bool old_format = false;  // no end flag after the data
        uint64_t data = 0;        // offset of the first data byte
    };

    size_t rawRead(void* buffer, size_t count);
    bool peek(uint64_t offset, void* out, size_t n);
    /** peek() up to `max_ahead` bytes beyond the current position instead of 4 KiB (a
     *  JPEG's bytes, decoded before MRPT decodes them). */
    bool peek(uint64_t offset, void* out, size_t n, uint64_t max_ahead);
    /** The `n` bytes at `offset` in the look-ahead buffer, read in as needed (at most
     *  `max_ahead` beyond the current position); nullptr when they are not there. Valid
     *  until the next read or look-ahead. */
    const uint8_t* lookAhead(uint64_t offset, size_t n, uint64_t max_ahead);
    void armFor(const std::string& class_name, bool old_format);
    /** The version and first data byte of the object whose class name was just read
     *  (pos_ is past the name); false on a short read or an impossible version. */
    bool readVersion(ObjectHeader& h);
    /** armFor for the classes whose counts need more than a fixed offset. */
    void armScan(const ObjectHeader& h);
    void armBearingRange(const ObjectHeader& h);
    void armRobotMovement(const ObjectHeader& h);
    void armRobotMovement3D(const ObjectHeader& h);
    /** armFor for MRPT classes HYMM does not consume but MRPT builds inside sensory frames
     *  (GuardedRawlogSensorLayouts.cpp); false if `h` is none of them. */
    bool armSensor(const ObjectHeader& h);
    void armRange(const ObjectHeader& h);
    void armImu(const ObjectHeader& h);
    void armVelodyne(const ObjectHeader& h);
    /** armSensor for the rarer classes (GuardedRawlogRareLayouts.cpp). */
    bool armRare(const ObjectHeader& h);
    void armRfid(const ObjectHeader& h);
    void armPointCloud(const ObjectHeader& h);
    void armRawDaq(const ObjectHeader& h);
    void armRotatingScan(const ObjectHeader& h);
    void armGpsMessages(const ObjectHeader& h);
    /** A Topcon PZS or SATS message of a GPS observation whose content starts at `p`:
     *  checks its counts; where it ends, 0 if not known. */
    uint64_t armTopcon(const ObjectHeader& h, bool sats, uint64_t p);
    void arm3DScan(const ObjectHeader& h);
    void armImage(const ObjectHeader& h);
    void armGasSensors(const ObjectHeader& h);
    void armRgbd360(const ObjectHeader& h);
    /** armImage's checks of the image data; where the data ends, 0 if not known. */
    uint64_t armImageData(const ObjectHeader& h);
    uint64_t armRawImage(const ObjectHeader& h);
    uint64_t armGreyImage(const ObjectHeader& h, uint64_t at);
    /** Refuses the JPEG of `n` bytes after the count at `at` if libjpeg cannot decode it. */
    void checkJpegDecodes(uint64_t at, uint32_t n);
    /** The byte count of a JPEG image at `at` and the size it decodes to. */
    uint64_t armJpeg(const ObjectHeader& h, uint64_t at);
    /** A count at `at` followed by elements of `element` bytes and `tail` bytes more
     *  (plus the end flag) before the object ends. */
    static Checkpoint countAt(const ObjectHeader& h, uint64_t at, uint64_t element, uint64_t tail,
                              const char* what);
    /** An image whose first dimension is read at `at`: `pixels` of `bytes` each, `fields`
     *  bytes of its own fields (from `at` on) and the end flag (Checkpoint::Pixels);
     *  `width`: bytes of each dimension (Checkpoint::width). */
    static Checkpoint pixelsAt(const ObjectHeader& h, uint64_t at, uint64_t pixels, uint64_t bytes,
                               uint64_t fields, const char* what, size_t width = 4);
    static uint64_t endFlagBytes(const ObjectHeader& h) { return h.old_format ? 0 : 1; }
    /** The class name MRPT will look up for the object serialised at `at`, with its
     *  namespace if written with one ("nullptr" for a null pointer); empty if the bytes
     *  cannot be read. */
    std::string classAt(uint64_t at);
    void checkCount(const Checkpoint& c);
    /** The checkpoint of the count after `c`'s elements (ending at `elements_end`), if
     *  `c` chains one. */
    void armNextInChain(const Checkpoint& c, uint64_t elements_end);
    [[noreturn]] void refuse(uint64_t n, uint64_t need, const Checkpoint& c, uint64_t left,
                             uint64_t reserved);
    /** Bytes after `at` that the counted containers being read still need at least for
     *  their remaining elements (see claims_); drops the claims that `at` has passed. */
    uint64_t reservedAfter(uint64_t at);
    bool peekHeader(uint64_t at, ObjectHeader& h, uint64_t max_ahead = kMaxPeek);
    /** Offset just past a serialised CPose3D (v0-3), CPose2D (v0-1), CPose3DQuat (v0),
     *  TCamera (v4-6), CPose3DPDFGaussian (v1) or CMatrixF/CMatrixD object starting at
     *  `at`, 0 if the bytes there are not one (or not within `max_ahead`). */
    uint64_t skipObject(uint64_t at, uint64_t max_ahead = kMaxPeek);
    /** skipObject() of the object whose header is `h`. */
    uint64_t objectEnd(const ObjectHeader& h, uint64_t max_ahead = kMaxPeek);

    /** An object being read: a current-format header went by, its end flag has not. */
    struct Frame
    {
        bool collection = false;  // a CActionCollection: its children must be actions
        bool element = false;     // a child of a collection
        bool sensory_frame = false;  // a CSensoryFrame: its children must be observations
        std::string name;            // without namespace
        int version = -1;            // once its version byte was read
        int poses = 0;               // pose objects read directly inside it (stereo observations)
    };
    /** At a class name MRPT just read (the header started at `at`): refuses an entry that
     *  is no action collection, sensory frame or observation, a child of an open
     *  CActionCollection that is not an action and a child of an open CSensoryFrame that
     *  is not an observation, and opens a frame for the object. */
    void trackHeader(const std::string& qualified, bool old_format, uint64_t at);
    /** Opens and closes frames for a read of `count` bytes that gave `n`, after one whose
     *  single byte was `prev` (-1 if it was wider); true if the read was one byte. */
    bool trackFrames(size_t count, size_t n, const uint8_t* bytes, int prev);
    /** At a pose object read directly inside a stereo observation (h: the pose's header):
     *  the label after the right camera's pose, or the features after the sensor's. */
    void armAfterStereoPose(const ObjectHeader& h);
    /** True if at `at` there is a serialised header of a registered class (or a null
     *  object), an end flag or the end of the data: what follows the end of a frame's
     *  element. */
    bool elementBoundaryAt(uint64_t at);
    /** armFor for a CActionCollection (old format: its single action's class). */
    void armCollection(const ObjectHeader& h);
    /** For a polymorphic slot MRPT reads without a null check (`where`, at byte `at`):
     *  throws RawlogSizeError unless `qualified` (as MRPT looks it up) names a class
     *  derived from `base`, or one MRPT does not know (it refuses those itself). */
    void requireClass(const std::string& qualified, const mrpt::rtti::TRuntimeClassId* base, uint64_t at,
                      const char* where);

    std::string path_;
    void* gz_ = nullptr;  // gzFile
    uint64_t total_ = 0;
    uint64_t pos_ = 0;
    uint64_t entry_start_ = std::numeric_limits<uint64_t>::max();
    std::string data_error_;
    std::string size_error_;
    bool cut_read_ = false;
    std::vector<uint8_t> ahead_;  // bytes read from zlib, the unconsumed ones from ahead_head_ (at pos_)
    size_t ahead_head_ = 0;
    std::vector<Checkpoint> checkpoints_;
    // Per accepted count of n elements of at least e bytes starting at s: s + (n - 1) e.
    // Read up to any p inside element k (p >= s + (k - 1) e), the elements after it still
    // need (n - k) e >= that - p bytes; past the elements the claim is negative (dropped).
    std::vector<uint64_t> claims_;
    int last_read_byte_ = -1;  // value of the previous read when it was one byte
    int old_header_len_ = -1;  // name length of an old-format header whose zeros were just read
    // The open objects, innermost last. A header opens a frame once its version byte is
    // read (pending_); a byte 0x88 read on its own closes the innermost one (MRPT reads the
    // end flag so), but a value can be 0x88 too, so the close is undone by what comes
    // next (popped_): the same byte was the length of an 8-character class name if the
    // next read is that name; it was a bool of an action if it closed an action or a
    // collection and the next read is not one byte (after an element MRPT reads the next
    // header's length byte or the collection's end flag, one byte each; every bool of
    // MRPT's actions is followed by wider fields). Valid files write bools as 0 or 1.
    std::vector<Frame> open_;
    std::optional<Frame> pending_;
    std::optional<Frame> popped_;
    bool reopened_ = false;  // the frame popped_ closed was reopened for a name read
};

}  // namespace hymm::io::detail
