// GuardedRawlogStream: where the counts lie in the serialised objects of the classes
// HYMM reads (the checkpoints armFor sets when a class name goes by), and which classes
// may appear where (trackHeader) and which objects are open (trackFrames).
#include "GuardedRawlogStream.h"

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDF.h>

#include <array>
#include <cstdint>
#include <string>

namespace hymm::io::detail
{
namespace
{
// CActionRobotMovement2D's Thrun motion model draws this many samples at most (MRPT's
// default is 300); each costs about 64 bytes, so the cap bounds that draw to 64 MiB.
constexpr uint32_t kMaxMotionModelParticles = 1000000;
// Smallest serialised 3x3 CMatrixD object, the only one MRPT accepts as a
// bearing-range covariance: header (length byte, a name of at least one byte, version),
// rows and columns, 9 doubles, end flag. The old header format is longer.
constexpr uint64_t kMinCovarianceBytes = 1 + 1 + 1 + 8 + 9 * 8 + 1;
}  // namespace

void GuardedRawlogStream::armFor(const std::string& qualified, bool old_format)
{
    // pos_ is just past the class name: the version comes next. Offsets below follow
    // MRPT 2.5's serializeFrom() of each class, for every version it still reads.
    ObjectHeader h;
    h.name = unqualified(qualified);
    h.old_format = old_format;
    if (!readVersion(h)) return;
    const int v = h.version;
    const uint64_t data = h.data;
    const std::string& name = h.name;
    if ((name == "CPose3DQuat" || name == "CPose3D") && !open_.empty()) armAfterStereoPose(h);
    if (name == "CSensoryFrame" && v <= 2)
    {
        // v0: ID (uint32) and a timestamp (uint64) before the count; v1: the ID.
        const uint64_t at = data + (v == 0 ? 12 : v == 1 ? 4 : 0);
        checkpoints_.push_back(countAt(h, at, kMinObjectBytes, 0, "observations"));
    }
    else if (name == "CActionCollection" && v == 0)
        armCollection(h);
    else if (name == "CObservation2DRangeScan" && v <= 7)
        armScan(h);
    else if (name == "CObservationBearingRange" && v <= 3)
        armBearingRange(h);
    else if (name == "CObservationOdometry" && v <= 2)
    {
        // odometry (CPose2D object), then the label, timestamp, and from v1 more fields.
        const uint64_t at = skipObject(data);
        if (at == 0) return;
        checkpoints_.push_back(countAt(h, at, 1, 8, "bytes of sensor label"));
    }
    else if (name == "CActionRobotMovement2D" && v <= 7)
        armRobotMovement(h);
    else if (name == "CActionRobotMovement3D" && v <= 1)
        armRobotMovement3D(h);
    else if (name == "CPosePDFParticles" && v <= 1)
        // v1: log weight and a TPose2D (x, y, phi): 4 doubles per particle, as MRPT stores
        // them;
        // v0: log weight and a CPose2D object of at least 22 bytes.
        checkpoints_.push_back(countAt(h, data, v == 1 ? 32 : 8 + 22, 0, "particles"));
    else if (name == "CPosePDFSOG" && v <= 2)
        // Per mode: log weight, mean (CPose2D object), the covariance's upper triangle
        // (6 floats in v1, doubles otherwise).
        checkpoints_.push_back(countAt(h, data, 8 + 22 + (v == 1 ? 24 : 48), 0, "modes"));
    else if (name == "CPosePDFGrid" && v == 0)
        // 8 doubles of limits and resolutions, 7 int32 sizes and indices, then the
        // cells as a vector of doubles.
        checkpoints_.push_back(countAt(h, data + 64 + 28, 8, 0, "grid cells"));
    else if (v == 0 && matrixElementBytes(name) != 0)
    {
        Checkpoint c = countAt(h, data, matrixElementBytes(name), 0, "matrix elements");
        c.kind = Checkpoint::Matrix;
        checkpoints_.push_back(c);
    }
    else
        armSensor(h);
}

void GuardedRawlogStream::armCollection(const ObjectHeader& h)
{
    checkpoints_.push_back(countAt(h, h.data, kMinObjectBytes, 0, "actions"));
    // Current-format collections have their actions checked as they go by (open_).
    // An old-format action has no end flag, so where the second one starts is not
    // known without its layout: the first is checked here, more are refused.
    uint32_t n = 0;
    if (!h.old_format || !peek(h.data, &n, 4) || n == 0) return;
    if (n > 1)
    {
        size_error_ = "holds an old-format (before MRPT 0.5.5) CActionCollection of " +
                      std::to_string(n) + " actions at byte " + std::to_string(h.data) +
                      "; only one action per such collection is read";
        throw RawlogSizeError(size_error_);
    }
    const std::string cls = classAt(h.data + 4);
    if (!cls.empty()) requireClass(cls, CLASS_ID(mrpt::obs::CAction), h.data + 4, kActionSlot);
}

bool GuardedRawlogStream::readVersion(ObjectHeader& h)
{
    if (h.old_format)
    {
        int32_t v = 0;
        if (!peek(pos_, &v, 4) || v < 0 || v > 255) return false;
        h.version = v;
        h.data = pos_ + 4;
    }
    else
    {
        uint8_t v = 0;
        if (!peek(pos_, &v, 1)) return false;
        h.version = v;
        h.data = pos_ + 1;
    }
    return true;
}

void GuardedRawlogStream::armScan(const ObjectHeader& h)
{
    const int v = h.version;
    const uint64_t data = h.data;
    // aperture (float), rightToLeft (bool), maxRange (float), sensorPose (CPose3D),
    // before v6 a covariance matrix object, then the beam count.
    uint64_t at = skipObject(data + 9);
    if (at != 0 && v < 6) at = skipObject(at);
    if (at == 0) return;
    // Per beam a float range and (from v1) a validity byte: MRPT allocates 9 bytes
    // per beam (range, validity, intensity). After the beams: stdError (v2+),
    // timestamp (v3+), beamAperture (v4+), the label's length and deltaPitch (v5+),
    // hasIntensity (v7).
    const uint64_t tail = (v >= 2 ? 4 : 0) + (v >= 3 ? 8 : 0) + (v >= 4 ? 4 : 0) +
                          (v >= 5 ? 8 : 0) + (v >= 7 ? 1 : 0);
    Checkpoint c = countAt(h, at, v == 0 ? 4 : 5, tail, "beams");
    if (v >= 5)
    {
        c.then[0] = {"bytes of sensor label", 4 + 8 + 4, 1, 4 + (v >= 7 ? 1u : 0u) + endFlagBytes(h)};
    }
    checkpoints_.push_back(c);
}

void GuardedRawlogStream::armBearingRange(const ObjectHeader& h)
{
    const int v = h.version;
    const uint64_t data = h.data;
    // min/max distance (floats), field of view (2 floats from v3, 1 before),
    // sensorLocationOnRobot (CPose3D), timestamp (v2+), validCovariances (v3+, then
    // three floats when false), then the count; each measurement range, yaw, pitch
    // (floats) and the landmark ID (int32), with valid covariances a 3x3 matrix
    // object, then the label (v1+).
    uint64_t at = skipObject(data + 8 + (v >= 3 ? 8 : 4));
    if (at == 0) return;
    if (v >= 2) at += 8;
    uint8_t valid_cov = 0;
    if (v >= 3)
    {
        if (!peek(at, &valid_cov, 1)) return;
        at += 1 + (valid_cov ? 0 : 12);
    }
    uint64_t element = 16;
    bool exact_stride = true;
    if (valid_cov)
    {
        // Every matrix MRPT writes here is 3x3: the first one gives the stride. Bytes
        // that are no such matrix (a flipped validCovariances flag) still bound the
        // count: MRPT sizes the vector before it reads the first covariance, so the
        // checkpoint is armed with the smallest 3x3 matrix object, and without the
        // label (its offset is unknown; MRPT fails on the first matrix anyway).
        uint32_t n = 0;
        if (!peek(at, &n, 4)) return;  // a short read: MRPT reports it
        const uint64_t first = at + 4 + 16;
        const uint64_t m = n > 0 ? skipObject(first) : 0;
        const bool parsed = m != 0 && m - first >= kMinCovarianceBytes;
        exact_stride = n == 0 || parsed;
        element += parsed ? m - first : kMinCovarianceBytes;
    }
    Checkpoint c = countAt(h, at, element, v >= 1 ? 4 : 0, "measurements");
    if (v >= 1 && exact_stride)
    {
        c.then[0] = {"bytes of sensor label", 0, 1, endFlagBytes(h)};
    }
    checkpoints_.push_back(c);
}

void GuardedRawlogStream::armRobotMovement(const ObjectHeader& h)
{
    const int v = h.version;
    const uint64_t data = h.data;
    // Versions 0-1 start with the pose PDF; later ones with the estimation method, and
    // the PDF follows unless it is emOdometry (0). MRPT casts the object it reads there to
    // a pose PDF and copies it through the pointer without a null check: a serialised
    // null object, or an object of another class (the cast gives null), was a
    // segmentation fault inside MRPT. Anything but a pose PDF class is refused here.
    int32_t method = -1;
    if (v <= 1 || (peek(data, &method, 4) && method != 0))
    {
        const uint64_t pdf = v <= 1 ? data : data + 4;
        const std::string cls = classAt(pdf);
        if (!cls.empty())
            requireClass(cls, CLASS_ID(mrpt::poses::CPosePDF), pdf, "a CActionRobotMovement2D's pose PDF");
        return;
    }
    // emOdometry stores the raw increment and the motion model; MRPT rebuilds the PDF
    // from them, drawing nParticlesCount samples for the Thrun model (1): that count is
    // not backed by bytes in the file, so it gets a fixed cap.
    if (v < 3 || method != 0) return;
    const uint64_t at = skipObject(data + 4);
    int32_t model = 0;
    if (at == 0 || !peek(at, &model, 4) || model == 0) return;
    Checkpoint c;
    c.kind = Checkpoint::Cap;
    c.offset = at + 4 + (v >= 4 ? 6 : 5) * 4;
    c.cap = kMaxMotionModelParticles;
    c.what = "motion-model particles";
    checkpoints_.push_back(c);
}

void GuardedRawlogStream::armRobotMovement3D(const ObjectHeader& h)
{
    // The estimation method (int32), the pose change (a CPose3DPDFGaussian object), the
    // velocity flags (a vector<bool>: count, one byte each; MRPT allocates a byte and a
    // bit per flag), the velocities (a float vector: count, 4 bytes each), and from v1
    // a timestamp.
    const uint64_t at = skipObject(h.data + 4);
    if (at == 0) return;
    const uint64_t stamp = h.version >= 1 ? 8 : 0;
    Checkpoint c = countAt(h, at, 1, 4 + stamp, "velocity flags");
    c.then[0] = {"velocities", 0, 4, stamp + endFlagBytes(h)};
    checkpoints_.push_back(c);
}

void GuardedRawlogStream::trackHeader(const std::string& qualified, bool old_format, uint64_t at)
{
    const bool null = qualified == "nullptr";
    // Bytes that only look like a header (a value with the high bit set, then as many
    // bytes) name no class; a real header naming none is refused by MRPT itself.
    const mrpt::rtti::TRuntimeClassId* id = null ? nullptr : mrpt::rtti::findRegisteredClass(qualified);
    if (!null && !id) return;
    // An abstract class (CPosePDF, CAction, CObservation, ...) has no constructor: MRPT
    // prints a warning and reads an empty pointer in its place, which its deserialisers
    // dereference (found by the rawlog fuzz target: a movement's pose PDF named
    // CPosePDF). No writer can produce one, so it is refused wherever it appears.
    if (id && !id->ptrCreateObject)
    {
        size_error_ = "names the abstract class '" + unqualified(qualified) +
                      "', which no rawlog can hold, at byte " + std::to_string(at);
        throw RawlogSizeError(size_error_);
    }
    // MRPT builds whatever class an entry or a frame's element names before the reader
    // or the frame casts it (to null): a planted map or scene object would be built with
    // the sizes it declares, which only these layouts' classes have checked.
    if (at == entry_start_ && !null)
    {
        const bool entry = id->derivedFrom(CLASS_ID(mrpt::obs::CActionCollection)) ||
                           id->derivedFrom(CLASS_ID(mrpt::obs::CSensoryFrame)) ||
                           id->derivedFrom(CLASS_ID(mrpt::obs::CObservation));
        if (!entry) requireClass(qualified, CLASS_ID(mrpt::obs::CObservation), at, "a rawlog entry");
    }
    const bool element = !open_.empty() && open_.back().collection;
    if (element) requireClass(qualified, CLASS_ID(mrpt::obs::CAction), at, kActionSlot);
    if (!open_.empty() && open_.back().sensory_frame)
        requireClass(qualified, CLASS_ID(mrpt::obs::CObservation), at, kObservationSlot);
    if (old_format) return;  // no end flag to close it (old-format collections: armFor)
    const std::string name = unqualified(qualified);
    const Frame f{name == "CActionCollection", element, name == "CSensoryFrame", name};
    if (null)
        open_.push_back(f);  // no version byte: its end flag is the next read
    else
        pending_ = f;
}

void GuardedRawlogStream::requireClass(const std::string& qualified, const mrpt::rtti::TRuntimeClassId* base,
                                       uint64_t at, const char* where)
{
    std::string what;
    if (qualified == "nullptr")
        what = "a null object";
    else
    {
        const auto* id = mrpt::rtti::findRegisteredClass(qualified);
        if (!id || id->derivedFrom(base)) return;
        what = "a '" + unqualified(qualified) + "'";
    }
    size_error_ = "holds " + what + " where " + where + " belongs, at byte " + std::to_string(at);
    throw RawlogSizeError(size_error_);
}

std::string GuardedRawlogStream::classAt(uint64_t at)
{
    // The header's name as MRPT looks it up (to a zero byte); a null pointer is an object
    // of class "nullptr" (with or without a version after it).
    uint8_t len = 0;
    if (!peek(at, &len, 1)) return "";
    const bool old_format = !(len & 0x80);
    len &= 0x7F;
    std::array<uint8_t, 128> name{};
    if (len == 0 || len > 120 || !peek(at + 1 + (old_format ? 3 : 0), name.data(), len)) return "";
    return classNameOf(name.data(), len);
}

GuardedRawlogStream::Checkpoint GuardedRawlogStream::pixelsAt(const ObjectHeader& h, uint64_t at, uint64_t pixels,
                                                              uint64_t bytes, uint64_t fields, const char* what,
                                                              size_t width)
{
    Checkpoint c = countAt(h, at, bytes, fields, what);
    c.kind = Checkpoint::Pixels;
    c.cap = pixels;
    c.width = width;
    return c;
}

GuardedRawlogStream::Checkpoint GuardedRawlogStream::countAt(
    const ObjectHeader& h, uint64_t at, uint64_t element, uint64_t tail, const char* what)
{
    Checkpoint c;
    c.offset = at;
    c.element_bytes = element;
    c.tail_bytes = tail + endFlagBytes(h);
    c.what = what;
    return c;
}

bool GuardedRawlogStream::trackFrames(size_t count, size_t n, const uint8_t* bytes, int prev)
{
    // Which objects are open (see open_): the version byte after a class name opens the
    // frame; a lone 0x88 closes one, unless what follows shows it was a value.
    bool version_byte = false;
    if (pending_)
    {
        if (count == 1 && n == 1)
        {
            open_.push_back(*pending_);
            open_.back().version = bytes[0];
            version_byte = true;
        }
        else if (reopened_ && !open_.empty())
            open_.pop_back();  // no version byte: no header, so the 0x88 did close it
        pending_.reset();
    }
    reopened_ = false;
    if (popped_)
    {
        // Reopened at once, so that the header's own check sees the right parent; closed
        // again if no version byte follows the name.
        const bool name_follows = prev == kEndFlag && n == count && n == (kEndFlag & 0x7Fu) &&
                                  mrpt::rtti::findRegisteredClass(classNameOf(bytes, n)) != nullptr;
        const bool wide_after_action = (popped_->collection || popped_->element) && count != 1;
        if (name_follows || wide_after_action) open_.push_back(*popped_);
        reopened_ = name_follows;
        popped_.reset();
    }
    if (n != 1) return false;
    if (!version_byte && bytes[0] == kEndFlag && !open_.empty())
    {
        popped_ = open_.back();
        open_.pop_back();
        // The end of a frame's observation is followed by the next observation's header
        // or by the frame's own end flag. A uint8 field of value 0x88 inside an
        // observation (a Topcon status byte, a CAN data byte) is followed by neither; taken
        // for a close it would have the observation's nested objects checked as frame
        // elements, and a valid file refused.
        if (!open_.empty() && open_.back().sensory_frame && !elementBoundaryAt(pos_))
        {
            open_.push_back(*popped_);
            popped_.reset();
        }
    }
    return true;
}

bool GuardedRawlogStream::elementBoundaryAt(uint64_t at)
{
    uint8_t b = 0;
    if (!peek(at, &b, 1)) return true;  // the end of the data: nothing left to check
    if (b == kEndFlag) return true;
    const std::string cls = classAt(at);
    return cls == "nullptr" || (!cls.empty() && mrpt::rtti::findRegisteredClass(cls) != nullptr);
}

}  // namespace hymm::io::detail
