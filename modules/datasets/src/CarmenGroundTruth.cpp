#include "hymm/datasets/CarmenGroundTruth.h"

#include <hymm/eval/metrics_report.h>
#include <hymm/io/RawlogReader.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <zlib.h>

#include <cmath>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace hymm::datasets
{
namespace
{
std::string where(const std::string& path, size_t line) { return path + ":" + std::to_string(line) + ": "; }

double finiteField(const std::string& s, const std::string& path, size_t line, const char* what)
{
    size_t used = 0;
    double v = 0;
    try
    {
        v = std::stod(s, &used);
    }
    catch (const std::exception&)
    {
        used = 0;
    }
    if (used != s.size() || !std::isfinite(v))
        throw std::runtime_error(where(path, line) + "FLASER " + what + " '" + s + "' is not a finite number");
    return v;
}

/** FLASER n r_1 .. r_n x y theta odom_x odom_y odom_theta ipc_timestamp host logger_timestamp */
CarmenLaserScan parseFlaser(const std::vector<std::string>& f, const std::string& path, size_t line)
{
    if (f.size() < 2) throw std::runtime_error(where(path, line) + "FLASER without a reading count");
    const double n = finiteField(f[1], path, line, "reading count");
    if (n < 0 || n != std::floor(n) || n > 100000)
        throw std::runtime_error(where(path, line) + "FLASER reading count '" + f[1] + "' is not a count");
    const size_t count = static_cast<size_t>(n);
    if (f.size() < 2 + count + 7)
        throw std::runtime_error(where(path, line) + "FLASER with " + std::to_string(count) + " readings has " +
                                 std::to_string(f.size()) + " fields, expected at least " +
                                 std::to_string(2 + count + 7));
    CarmenLaserScan s;
    s.ranges.reserve(count);
    for (size_t i = 0; i < count; ++i) s.ranges.push_back(finiteField(f[2 + i], path, line, "range"));
    for (int k = 0; k < 3; ++k) s.pose[k] = finiteField(f[2 + count + k], path, line, "pose");
    s.t = finiteField(f[2 + count + 6], path, line, "ipc_timestamp");
    return s;
}

/** A scan's ranges on the common grid: the key two equal scans share. */
std::vector<long> rangeKey(const std::vector<double>& ranges, double resolution)
{
    std::vector<long> k;
    k.reserve(ranges.size());
    for (double r : ranges) k.push_back(std::lround(r / resolution));
    return k;
}
}  // namespace

std::vector<CarmenLaserScan> readCarmenLaserScans(const std::string& path)
{
    // gzopen reads plain files unchanged, so one reader serves both.
    std::unique_ptr<gzFile_s, decltype(&gzclose)> gz(gzopen(path.c_str(), "rb"), &gzclose);
    if (!gz) throw std::runtime_error("cannot open CARMEN log '" + path + "'");
    std::vector<CarmenLaserScan> out;
    std::string line;
    char buf[65536];
    size_t line_no = 0;
    bool more = true;
    while (more)
    {
        // A line may be longer than the buffer: read until its newline.
        line.clear();
        more = false;
        while (gzgets(gz.get(), buf, sizeof(buf)))
        {
            more = true;
            line += buf;
            if (!line.empty() && line.back() == '\n') break;
        }
        if (!more) break;
        ++line_no;
        if (line.back() != '\n')
        {
            // A last line without its newline: the file's end, or a read error that cut it.
            int err = Z_OK;
            gzerror(gz.get(), &err);
            if (err != Z_OK && err != Z_STREAM_END)
                throw std::runtime_error("CARMEN log '" + path + "': read error in line " + std::to_string(line_no));
        }
        if (line.compare(0, 7, "FLASER ") != 0) continue;
        std::istringstream in(line);
        std::vector<std::string> fields;
        for (std::string w; in >> w;) fields.push_back(w);
        out.push_back(parseFlaser(fields, path, line_no));
    }
    int err = Z_OK;
    gzerror(gz.get(), &err);
    if (err != Z_OK && err != Z_STREAM_END)
        throw std::runtime_error("CARMEN log '" + path + "': read error after line " + std::to_string(line_no));
    return out;
}

ScanPairing pairScansByRanges(const std::string& rawlog, const std::vector<CarmenLaserScan>& carmen,
                              double resolution_m)
{
    if (!(resolution_m > 0)) throw std::invalid_argument("pairScansByRanges: resolution must be > 0");
    struct Seen
    {
        size_t scan = 0;
        double t = 0;
        size_t count = 0;
    };
    std::map<std::vector<long>, Seen> by_key;
    ScanPairing out;
    io::RawlogReader reader(rawlog);
    io::RawlogEntry e;
    auto add = [&](const mrpt::obs::CObservation::Ptr& o) {
        const auto* s = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(o.get());
        if (!s) return;
        std::vector<double> r(s->getScanSize());
        for (size_t i = 0; i < r.size(); ++i) r[i] = s->getScanRange(i);
        auto& seen = by_key[rangeKey(r, resolution_m)];
        if (seen.count++ == 0)
        {
            seen.scan = out.rawlog_scans;
            seen.t = mrpt::Clock::toDouble(s->timestamp);
        }
        ++out.rawlog_scans;
    };
    while (reader.next(e))
    {
        if (e.frame)
            for (const auto& o : *e.frame) add(o);
        if (e.observation) add(e.observation);
    }

    out.carmen_scans = carmen.size();
    for (const auto& c : carmen)
    {
        const auto it = by_key.find(rangeKey(c.ranges, resolution_m));
        if (it == by_key.end())
            ++out.unmatched;
        else if (it->second.count > 1)
            ++out.ambiguous;
        else if (!out.matches.empty() && it->second.scan <= out.matches.back().scan)
            ++out.out_of_order;
        else
            out.matches.push_back({it->second.scan, it->second.t, c.pose});
    }
    return out;
}

PairedPoses posesAtPairs(const std::vector<io::StampedPose2D>& path, const ScanPairing& pairing)
{
    if (path.size() != pairing.rawlog_scans)
        throw std::invalid_argument("the path has " + std::to_string(path.size()) + " poses and the rawlog " +
                                    std::to_string(pairing.rawlog_scans) +
                                    " scans: scoring at the paired scans needs one pose per scan");
    PairedPoses out;
    for (const auto& m : pairing.matches)
    {
        out.estimate.push_back(path[m.scan]);
        out.truth.push_back({path[m.scan].t, m.pose.x(), m.pose.y(), m.pose.z()});
    }
    return out;
}

PairedPathScore scorePathAtPairs(const std::vector<io::StampedPose2D>& path, const ScanPairing& pairing)
{
    const PairedPoses p = posesAtPairs(path, pairing);
    if (p.estimate.size() < 2)
        throw std::invalid_argument("only " + std::to_string(p.estimate.size()) +
                                    " scan(s) paired with the corrected log: nothing to score");
    eval::TrajectoryEvaluator::Options o;
    o.association = eval::TrajectoryEvaluator::Association::Index;
    o.align = true;
    return {eval::TrajectoryEvaluator(o).evaluate(p.estimate, p.truth), eval::relativePoseError(p.estimate, p.truth)};
}

eval::MetricsJson pairedScoreMetrics(const ScanPairing& pairing, const PairedPathScore& score)
{
    eval::MetricsJson j;
    auto& c = j.object("pairing");
    c.set("paired", pairing.matches.size());
    c.set("rawlog_scans", pairing.rawlog_scans);
    c.set("corrected_scans", pairing.carmen_scans);
    c.set("unmatched", pairing.unmatched);
    c.set("ambiguous", pairing.ambiguous);
    c.set("out_of_order", pairing.out_of_order);
    eval::writeTrajectoryMetrics(j.object("path"), score.absolute);
    eval::writeRelativePoseMetrics(j.object("relative"), score.relative);
    return j;
}

}  // namespace hymm::datasets
