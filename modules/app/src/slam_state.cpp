// hymm-slam's saved run state: header, checksum, config check, keyframes (slam_state.h).
#include <hymm/app/slam_state.h>

#include <hymm/core/StrictConfigFile.h>
#include <hymm/core/state_archive.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace hymm::app
{
using namespace hymm::core::state;

namespace
{
constexpr char kMagic[8] = {'H', 'Y', 'M', 'M', 'S', 'T', 'A', 'T'};
constexpr size_t kHeaderBytes = 8 + 4 + 8 + 8;

std::uint64_t fnv1a(const unsigned char* p, size_t n)
{
    std::uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

template <class T>
void putLE(std::string& s, T v)
{
    for (size_t i = 0; i < sizeof(T); ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
template <class T>
T getLE(const unsigned char* p)
{
    T v = 0;
    for (size_t i = 0; i < sizeof(T); ++i) v |= static_cast<T>(p[i]) << (8 * i);
    return v;
}

/** The first line where two fingerprints differ, for the error message. */
std::string firstDifference(const std::string& saved, const std::string& now)
{
    std::istringstream a(saved), b(now);
    std::string la, lb;
    while (true)
    {
        const bool ha = static_cast<bool>(std::getline(a, la)), hb = static_cast<bool>(std::getline(b, lb));
        if (!ha && !hb) return "";
        if (!ha) return "the config has '" + lb + "', the state has not";
        if (!hb) return "the state has '" + la + "', the config has not";
        if (la != lb) return "the state has '" + la + "', the config '" + lb + "'";
    }
}
}  // namespace

std::string configFingerprint(const std::string& ini_path)
{
    const core::StrictConfigFile file(ini_path);
    const auto& cfg = file.config();
    std::vector<std::string> sections;
    cfg.getAllSections(sections);
    std::map<std::string, std::map<std::string, std::string>> sorted;
    for (const auto& s : sections)
    {
        std::vector<std::string> keys;
        cfg.getAllKeys(s, keys);
        for (const auto& k : keys) sorted[s][k] = cfg.read_string(s, k, "", false);
    }
    std::string out;
    for (const auto& [s, keys] : sorted)
        for (const auto& [k, v] : keys) out += "[" + s + "] " + k + " = " + v + "\n";
    return out;
}

void KeyframeRecorder::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "KeyframeRecorder");
    out << static_cast<std::uint64_t>(path_size_);
    writeSize(out, frames_.size());
    for (const auto& [i, sf] : frames_) out << static_cast<std::uint64_t>(i) << *sf;
    out << has_odometry_ << static_cast<std::uint64_t>(predictions_seen_) << odometry_now_.x()
        << odometry_now_.y() << odometry_now_.phi();
    writeSize(out, odometry_.size());
    for (const auto& p : odometry_) out << p.x() << p.y() << p.phi();
}

void KeyframeRecorder::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "KeyframeRecorder");
    const size_t path_size = readU64(in);
    std::vector<std::pair<size_t, mrpt::obs::CSensoryFrame::Ptr>> frames(readSize(in, "keyframe"));
    for (auto& [i, sf] : frames)
    {
        i = readU64(in);
        sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(in.ReadObject());
        if (!sf || i >= path_size) throw std::runtime_error("corrupt state: keyframe");
    }
    const bool has_odometry = readBool(in);
    const size_t predictions_seen = readU64(in);
    double now_x = 0, now_y = 0, now_phi = 0;
    in >> now_x >> now_y >> now_phi;
    // Either no odometry or one pose per keyframe (record()).
    const size_t n = readSize(in, "keyframe odometry");
    if (n != (has_odometry ? frames.size() : 0)) throw std::runtime_error("corrupt state: keyframe odometry");
    std::vector<mrpt::poses::CPose2D> odometry(n);
    for (auto& p : odometry)
    {
        double x = 0, y = 0, phi = 0;
        in >> x >> y >> phi;
        p = mrpt::poses::CPose2D(x, y, phi);
    }
    path_size_ = path_size;
    frames_ = std::move(frames);
    has_odometry_ = has_odometry;
    predictions_seen_ = predictions_seen;
    odometry_now_ = mrpt::poses::CPose2D(now_x, now_y, now_phi);
    odometry_ = std::move(odometry);
}

void saveRunState(const std::string& path, const RunInfo& info, const denseslam::DenseSlam& slam,
                  const KeyframeRecorder& keyframes)
{
    mrpt::io::CMemoryStream mem;
    {
        auto ar = mrpt::serialization::archiveFrom(mem);
        ar << info.config << info.rawlog << info.rawlog_entries << info.entries;
        slam.saveState(ar);
        keyframes.saveState(ar);
        writeTag(ar, "end of state");
    }
    const auto* data = static_cast<const unsigned char*>(mem.getRawBufferData());
    const size_t n = mem.getTotalBytesCount();
    std::string header(kMagic, sizeof(kMagic));
    putLE<std::uint32_t>(header, kRunStateVersion);
    putLE<std::uint64_t>(header, n);
    putLE<std::uint64_t>(header, fnv1a(data, n));
    const std::string tmp = path + ".part";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        f.write(header.data(), static_cast<std::streamsize>(header.size()));
        f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(n));
        if (!f.flush()) throw std::runtime_error("cannot write the run state '" + path + "'");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
    {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write the run state '" + path + "'");
    }
}

namespace
{
/** The payload of a state file, after the header checks. */
std::string readPayload(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error("cannot open the run state '" + path + "'");
    const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
    if (bytes.size() < sizeof(kMagic) || std::memcmp(p, kMagic, sizeof(kMagic)) != 0)
        throw std::runtime_error("'" + path + "' is not a hymm-slam run state (no HYMMSTAT header)");
    if (bytes.size() < kHeaderBytes)
        throw std::runtime_error("run state '" + path + "' is truncated (" + std::to_string(bytes.size()) +
                                 " bytes, shorter than its header)");
    const auto version = getLE<std::uint32_t>(p + 8);
    if (version != kRunStateVersion)
        throw std::runtime_error("run state '" + path + "' has format version " + std::to_string(version) +
                                 "; this hymm-slam reads version " + std::to_string(kRunStateVersion));
    const auto size = getLE<std::uint64_t>(p + 12);
    if (bytes.size() - kHeaderBytes < size)
        throw std::runtime_error("run state '" + path + "' is truncated: " +
                                 std::to_string(bytes.size() - kHeaderBytes) + " of " + std::to_string(size) +
                                 " bytes of state");
    if (bytes.size() - kHeaderBytes > size)
        throw std::runtime_error("run state '" + path + "' is corrupt: " +
                                 std::to_string(bytes.size() - kHeaderBytes - size) + " bytes after the state");
    if (fnv1a(p + kHeaderBytes, size) != getLE<std::uint64_t>(p + 20))
        throw std::runtime_error("run state '" + path + "' is corrupt (checksum mismatch)");
    return bytes.substr(kHeaderBytes);
}
}  // namespace

RunInfo loadRunState(const std::string& path, const std::string& config, denseslam::DenseSlam& slam,
                     KeyframeRecorder& keyframes)
{
    const std::string payload = readPayload(path);
    mrpt::io::CMemoryStream mem;
    mem.assignMemoryNotOwn(payload.data(), payload.size());
    auto ar = mrpt::serialization::archiveFrom(mem);
    RunInfo info;
    try
    {
        ar >> info.config >> info.rawlog >> info.rawlog_entries >> info.entries;
        if (info.config != config)
            throw std::runtime_error("it was saved under a different config: " +
                                     firstDifference(info.config, config));
        slam.loadState(ar);
        keyframes.loadState(ar);
        expectTag(ar, "end of state");
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error("cannot resume from run state '" + path + "': " + e.what());
    }
    return info;
}

}  // namespace hymm::app
