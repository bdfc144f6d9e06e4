// The delayed store's state for a saved run (hymm-slam --save-state / --resume): the
// stored scans (their passive pose ids, returns and noise), the potential regions, the
// id counters and the last time; the passive blocks themselves are the filter's state.
#include "hymm/uif/DelayedDenseStore.h"

#include <hymm/core/state_archive.h>

namespace hymm::uif
{
using namespace hymm::core::state;

void PotentialRegionSet::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "PotentialRegionSet");
    writeSize(out, regions_.size());
    for (const auto& [id, r] : regions_)
    {
        writeLong(out, r.id);
        for (long v : r.vertex_ids) writeLong(out, v);
    }
    writeLong(out, next_id_);
}

void PotentialRegionSet::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "PotentialRegionSet");
    std::map<long, PotentialRegion> regions;
    const size_t n = readSize(in, "potential region");
    for (size_t i = 0; i < n; ++i)
    {
        PotentialRegion r;
        r.id = readLong(in);
        for (long& v : r.vertex_ids) v = readLong(in);
        if (!regions.emplace(r.id, r).second)
            throw std::runtime_error("corrupt state: potential region " + std::to_string(r.id) + " twice");
    }
    next_id_ = readLong(in);
    regions_ = std::move(regions);
}

void DelayedDenseStore::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "DelayedDenseStore");
    writeSize(out, scans_.size());
    for (const StoredScan& s : scans_)
    {
        writeLong(out, s.scan_id);
        writeLong(out, s.passive_id);
        out << s.time;
        writeMatrix(out, s.sensor);
        writeMatrix(out, s.R);
        writeSize(out, s.points.size());
        for (const StoredPoint& p : s.points)
        {
            out << p.z.x() << p.z.y();
            writeLong(out, p.potential_region);
            writeLong(out, p.tag);
        }
    }
    out << static_cast<std::uint64_t>(num_points_);
    potential_.saveState(out);
    writeLong(out, next_scan_id_);
    writeLong(out, next_passive_id_);
    out << last_time_;
}

void DelayedDenseStore::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "DelayedDenseStore");
    std::deque<StoredScan> scans(readSize(in, "stored scan"));
    for (StoredScan& s : scans)
    {
        s.scan_id = readLong(in);
        s.passive_id = readLong(in);
        in >> s.time;
        readMatrix(in, s.sensor, "stored scan sensor pose");
        readMatrix(in, s.R, "stored scan noise");
        s.points.resize(readSize(in, "stored return"));
        for (StoredPoint& p : s.points)
        {
            in >> p.z.x() >> p.z.y();
            p.potential_region = readLong(in);
            p.tag = readLong(in);
        }
    }
    num_points_ = readU64(in);
    potential_.loadState(in);
    next_scan_id_ = readLong(in);
    next_passive_id_ = readLong(in);
    in >> last_time_;
    scans_ = std::move(scans);
}

}  // namespace hymm::uif
