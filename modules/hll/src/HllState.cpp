// High-level landmarks' state for a saved run (hymm-slam --save-state / --resume): every
// value bit for bit (core/state_archive.h), the tracker through Scan-SLAM's own state.
#include <hymm/core/state_archive.h>

#include <stdexcept>

#include "hymm/hll/HighLevelLandmarks.h"

namespace hymm::hll
{
using namespace hymm::core::state;

namespace
{
/** Every counter of HighLevelLandmarks::Stats, in the state's order (a new counter goes
 *  at the end, with a new state version). */
std::vector<size_t*> counters(HighLevelLandmarks::Stats& s)
{
    return {&s.searches, &s.regions_searched, &s.components_dropped, &s.corners_near_landmark,
            &s.corners, &s.proposed, &s.accepted, &s.rejected_few_gaussians, &s.rejected_short_outline,
            &s.rejected_overlap_landmark, &s.rejected_overlap_candidate, &s.init_attempts,
            &s.init_align_failed, &s.initialised, &s.lost};
}

void writeRect(mrpt::serialization::CArchive& out, const OrientedRect& r)
{
    writeMatrix(out, r.centre);
    out << r.phi;
    writeMatrix(out, r.half);
}

void readRect(mrpt::serialization::CArchive& in, OrientedRect& r)
{
    readMatrix(in, r.centre, "rectangle centre");
    in >> r.phi;
    readMatrix(in, r.half, "rectangle size");
}

void writeSearch(mrpt::serialization::CArchive& out, const HllDetector::Search& s)
{
    out << s.t;
    writeMatrix(out, s.lo);
    writeMatrix(out, s.hi);
    out << static_cast<std::uint64_t>(s.regions) << static_cast<std::uint64_t>(s.regions_degenerate)
        << static_cast<std::uint64_t>(s.components_dropped) << static_cast<std::uint64_t>(s.corners_near_landmark);
    writeSize(out, s.corners.size());
    for (const Vec2& c : s.corners) writeMatrix(out, c);
    writeSize(out, s.candidates.size());
    for (const auto& c : s.candidates)
    {
        writeMatrix(out, c.a);
        writeMatrix(out, c.b);
        writeRect(out, c.rect);
        out << static_cast<std::uint64_t>(c.gaussians) << c.outline_m << static_cast<std::int32_t>(c.outcome);
    }
    writeSize(out, s.gaussians.size());
    for (const auto& g : s.gaussians)
    {
        writeMatrix(out, g.mean);
        writeMatrix(out, g.cov);
    }
}

void readSearch(mrpt::serialization::CArchive& in, HllDetector::Search& s)
{
    in >> s.t;
    readMatrix(in, s.lo, "search box");
    readMatrix(in, s.hi, "search box");
    s.regions = readU64(in);
    s.regions_degenerate = readU64(in);
    s.components_dropped = readU64(in);
    s.corners_near_landmark = readU64(in);
    s.corners.resize(readSize(in, "corner"));
    for (Vec2& c : s.corners) readMatrix(in, c, "corner");
    s.candidates.resize(readSize(in, "candidate"));
    for (auto& c : s.candidates)
    {
        readMatrix(in, c.a, "candidate corner");
        readMatrix(in, c.b, "candidate corner");
        readRect(in, c.rect);
        c.gaussians = readU64(in);
        in >> c.outline_m;
        std::int32_t outcome = 0;
        in >> outcome;
        if (outcome < 0 || outcome > static_cast<std::int32_t>(HllDetector::Outcome::overlaps_candidate))
            throw std::runtime_error("corrupt state: candidate outcome " + std::to_string(outcome));
        c.outcome = static_cast<HllDetector::Outcome>(outcome);
    }
    s.gaussians.resize(readSize(in, "search Gaussian"));
    for (auto& g : s.gaussians)
    {
        readMatrix(in, g.mean, "search Gaussian");
        readMatrix(in, g.cov, "search Gaussian covariance");
    }
}
}  // namespace

void HighLevelLandmarks::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "HighLevelLandmarks");
    writeSize(out, hlls_.size());
    for (const Hll& h : hlls_)
    {
        out << static_cast<std::uint64_t>(h.index);
        writeRect(out, h.rect);
        h.tpl.saveState(out);
        out << static_cast<std::uint64_t>(h.gaussians) << h.outline_m << h.t_accepted;
        writeLong(out, h.landmark_id);
        out << h.t_initialised;
    }
    writeSize(out, searches_.size());
    for (const auto& s : searches_) writeSearch(out, s);
    auto st = stats_;
    writeCounters(out, counters(st));
    out << last_search_t_;
    tracker_->saveState(out);
    writeTag(out, "HighLevelLandmarks end");
}

void HighLevelLandmarks::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "HighLevelLandmarks");
    hlls_.resize(readSize(in, "high-level landmark"));
    for (Hll& h : hlls_)
    {
        h.index = readU64(in);
        readRect(in, h.rect);
        h.tpl.loadState(in);
        h.gaussians = readU64(in);
        in >> h.outline_m >> h.t_accepted;
        h.landmark_id = readLong(in);
        in >> h.t_initialised;
    }
    searches_.resize(readSize(in, "search"));
    for (auto& s : searches_) readSearch(in, s);
    stats_ = Stats{};
    readCounters(in, counters(stats_), "high-level landmark counter");
    in >> last_search_t_;
    tracker_->loadState(in);
    expectTag(in, "HighLevelLandmarks end");
}

}  // namespace hymm::hll
