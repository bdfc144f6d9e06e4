/**
 * @file RevisitLog.cpp
 * @brief Revisits of landmarks (RevisitLog.h).
 */
#include "hymm/scanslam/RevisitLog.h"

#include <hymm/core/state_archive.h>
#include <mrpt/system/datetime.h>

namespace hymm::scanslam
{
using namespace hymm::core::state;

void RevisitLog::setScanTime(mrpt::Clock::time_point t)
{
    if (t == INVALID_TIMESTAMP) return;
    now_ = mrpt::Clock::toDouble(t);
    if (!has_time_) first_ = now_;
    has_time_ = true;
}

void RevisitLog::created(long id) { seen_[id] = {now_, now_}; }

void RevisitLog::updated(long id, bool wide, double gap_s)
{
    auto it = seen_.find(id);
    if (it == seen_.end())
    {
        created(id);
        return;
    }
    const double unseen = now_ - it->second.second;
    if (unseen >= gap_s && unseen > 0) revisits_.push_back({now_ - first_, id, unseen, now_ - it->second.first, wide});
    it->second.second = now_;
}

void RevisitLog::save(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "RevisitLog");
    out << now_ << first_ << has_time_;
    writeSize(out, seen_.size());
    for (const auto& [id, t] : seen_)
    {
        writeLong(out, id);
        out << t.first << t.second;
    }
    writeSize(out, revisits_.size());
    for (const Revisit& r : revisits_)
    {
        writeLong(out, r.id);
        out << r.t << r.unseen_s << r.age_s << r.wide;
    }
}

void RevisitLog::load(mrpt::serialization::CArchive& in)
{
    expectTag(in, "RevisitLog");
    in >> now_ >> first_;
    has_time_ = readBool(in);
    seen_.clear();
    const size_t n = readSize(in, "landmark seen times");
    for (size_t i = 0; i < n; ++i)
    {
        auto& t = seen_[readLong(in)];
        in >> t.first >> t.second;
    }
    revisits_.resize(readSize(in, "revisit"));
    for (Revisit& r : revisits_)
    {
        r.id = readLong(in);
        in >> r.t >> r.unseen_s >> r.age_s;
        r.wide = readBool(in);
    }
}

}  // namespace hymm::scanslam
