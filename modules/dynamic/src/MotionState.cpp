// The motion layers' state for a saved run (hymm-slam --save-state / --resume): every
// value bit for bit (core/state_archive.h), so a resumed run marks exactly the cells the
// uninterrupted one would have.
#include <hymm/core/state_archive.h>

#include <algorithm>
#include <stdexcept>

#include "hymm/dynamic/MotionDetector.h"
#include "hymm/dynamic/MotionLayer.h"
#include "hymm/dynamic/SlamMotionHook.h"

namespace hymm::dynamic
{
using namespace hymm::core::state;

namespace
{
/** A grid's cell count from its saved sizes, checked against the saved cells. */
void checkGrid(int nx, int ny, size_t cells, const char* what)
{
    if (nx < 0 || ny < 0 || static_cast<size_t>(nx) * static_cast<size_t>(ny) != cells)
        throw std::runtime_error(std::string("corrupt state: ") + what + " grid " + std::to_string(nx) +
                                 "x" + std::to_string(ny) + " holds " + std::to_string(cells) + " cells");
}

void writeDifference(mrpt::serialization::CArchive& out, const Difference& d)
{
    out << static_cast<std::int32_t>(d.nx) << static_cast<std::int32_t>(d.ny);
    writeValues(out, d.raw);
    writeValues(out, d.filtered);
    writeValues(out, d.mask);
}

void readDifference(mrpt::serialization::CArchive& in, Difference& d)
{
    std::int32_t nx = 0, ny = 0;
    in >> nx >> ny;
    d.nx = nx;
    d.ny = ny;
    readValues(in, d.raw, "difference cell");
    readValues(in, d.filtered, "difference cell");
    readValues(in, d.mask, "difference cell");
    if (!d.raw.empty() || !d.filtered.empty() || !d.mask.empty())
    {
        checkGrid(nx, ny, d.raw.size(), "difference");
        checkGrid(nx, ny, d.mask.size(), "difference mask");
    }
}

void writeSnapshot(mrpt::serialization::CArchive& out, const std::optional<OccupancySnapshot>& s)
{
    out << s.has_value();
    if (s) s->saveState(out);
}

void readSnapshot(mrpt::serialization::CArchive& in, std::optional<OccupancySnapshot>& s)
{
    s.reset();
    if (!readBool(in)) return;
    s.emplace();
    s->loadState(in);
}
}  // namespace

void MotionLayer::saveState(mrpt::serialization::CArchive& out) const
{
    out << origin_.x() << origin_.y() << cell_ << static_cast<std::int32_t>(nx_)
        << static_cast<std::int32_t>(ny_) << static_cast<std::uint64_t>(count_);
    writeValues(out, bits_);
}

void MotionLayer::loadState(mrpt::serialization::CArchive& in)
{
    std::int32_t nx = 0, ny = 0;
    in >> origin_.x() >> origin_.y() >> cell_ >> nx >> ny;
    count_ = readU64(in);
    readValues(in, bits_, "motion cell");
    checkGrid(nx, ny, bits_.size(), "motion layer");
    nx_ = nx;
    ny_ = ny;
}

void OccupancySnapshot::saveState(mrpt::serialization::CArchive& out) const
{
    out << t << origin.x() << origin.y() << cell_size << static_cast<std::int32_t>(nx)
        << static_cast<std::int32_t>(ny);
    writeValues(out, p);
    writeValues(out, inside);
}

void OccupancySnapshot::loadState(mrpt::serialization::CArchive& in)
{
    std::int32_t sx = 0, sy = 0;
    in >> t >> origin.x() >> origin.y() >> cell_size >> sx >> sy;
    nx = sx;
    ny = sy;
    readValues(in, p, "snapshot cell");
    readValues(in, inside, "snapshot cell");
    checkGrid(nx, ny, p.size(), "snapshot");
    checkGrid(nx, ny, inside.size(), "snapshot");
}

void MotionDetector::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "MotionDetector");
    // By id (the map is hashed): the same bytes whatever the insertion history.
    std::vector<long> ids;
    ids.reserve(regions_.size());
    for (const auto& kv : regions_) ids.push_back(kv.first);
    std::sort(ids.begin(), ids.end());
    writeSize(out, ids.size());
    for (const long id : ids)
    {
        const RegionState& st = regions_.at(id);
        writeLong(out, id);
        st.slow.saveState(out);
        st.fast.saveState(out);
        writeSnapshot(out, st.fast_ref);
        writeSnapshot(out, st.slow_ref);
        out << st.seen;
    }
    writeIds(out, in_view_);
    // The queue in its pop order (a copy; pushing them back rebuilds the same order).
    auto due = slow_due_;
    writeSize(out, due.size());
    for (; !due.empty(); due.pop())
    {
        out << due.top().first;
        writeLong(out, due.top().second);
    }
    for (const LastDifference* last : {&last_slow_, &last_fast_})
    {
        writeLong(out, last->region);
        out << last->t_then << last->t_now;
        writeDifference(out, last->diff);
    }
    saveTiles(out);
    writeTag(out, "MotionDetector end");
}

void MotionDetector::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "MotionDetector");
    regions_.clear();
    const size_t n = readSize(in, "motion region");
    for (size_t i = 0; i < n; ++i)
    {
        const long id = readLong(in);
        RegionState st;
        st.slow.loadState(in);
        st.fast.loadState(in);
        readSnapshot(in, st.fast_ref);
        readSnapshot(in, st.slow_ref);
        st.seen = readBool(in);
        regions_[id] = std::move(st);
    }
    in_view_ = readIds(in, "region in view");
    std::sort(in_view_.begin(), in_view_.end());
    in_view_.erase(std::unique(in_view_.begin(), in_view_.end()), in_view_.end());
    slow_due_ = {};
    const size_t nd = readSize(in, "slow differencing due");
    for (size_t i = 0; i < nd; ++i)
    {
        const double t = readDouble(in);
        slow_due_.emplace(t, readLong(in));
    }
    for (LastDifference* last : {&last_slow_, &last_fast_})
    {
        last->region = readLong(in);
        in >> last->t_then >> last->t_now;
        readDifference(in, last->diff);
    }
    loadTiles(in);
    expectTag(in, "MotionDetector end");
}

void MotionDetector::saveTiles(mrpt::serialization::CArchive& out) const
{
    // The fallback tiles' ids: their state is in the regions' table.
    writeSize(out, tile_ids_.size());
    for (const auto& [key, id] : tile_ids_)
    {
        writeLong(out, key.anchor);
        out << static_cast<std::int32_t>(key.ix) << static_cast<std::int32_t>(key.iy)
            << static_cast<std::int32_t>(key.half);
        writeLong(out, id);
    }
    writeLong(out, next_tile_id_);
    out << tile_m_ << tile_reach_m_;
}

void MotionDetector::loadTiles(mrpt::serialization::CArchive& in)
{
    tile_ids_.clear();
    tile_keys_.clear();
    marked_tile_anchors_.clear();
    const size_t nt = readSize(in, "motion tile");
    for (size_t i = 0; i < nt; ++i)
    {
        dense::FallbackTileKey key;
        key.anchor = readLong(in);
        std::int32_t ix = 0, iy = 0, half = 0;
        in >> ix >> iy >> half;
        key.ix = ix;
        key.iy = iy;
        key.half = half;
        const long id = readLong(in);
        if (!isTile(id) || (half != 0 && half != 1) || !tile_keys_.emplace(id, key).second ||
            !tile_ids_.emplace(key, id).second)
            throw std::runtime_error("corrupt state: motion tile id " + std::to_string(id));
    }
    next_tile_id_ = readLong(in);
    in >> tile_m_ >> tile_reach_m_;
    if (!isTile(next_tile_id_) || !(tile_m_ >= 0) || !(tile_reach_m_ >= 0))
        throw std::runtime_error("corrupt state: motion tiles' next id or geometry");
    for (const auto& kv : tile_keys_)
        if (kv.first >= next_tile_id_)
            throw std::runtime_error("corrupt state: motion tile id " + std::to_string(kv.first) + " not below the next id");
    for (const auto& [id, st] : regions_)
    {
        if (!isTile(id)) continue;
        if (!tile_keys_.count(id))
            throw std::runtime_error("corrupt state: motion state of unknown tile id " + std::to_string(id));
        noteTileMarks(id, false, hasMarks(id));
    }
}

void SlamMotionHook::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "SlamMotionHook");
    detector_.saveState(out);
    for (size_t v : {stats_.creations_blocked, stats_.flagged_dropped, stats_.landmarks_flagged,
                     stats_.landmarks_pruned, stats_.fast_differencings, stats_.slow_differencings})
        out << static_cast<std::uint64_t>(v);
    writeIds(out, std::vector<long>(flagged_.begin(), flagged_.end()));
    writeSize(out, last_seen_.size());
    for (const auto& [id, t] : last_seen_)
    {
        writeLong(out, id);
        out << t;
    }
    writeTag(out, "SlamMotionHook end");
}

void SlamMotionHook::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "SlamMotionHook");
    detector_.loadState(in);
    for (size_t* v : {&stats_.creations_blocked, &stats_.flagged_dropped, &stats_.landmarks_flagged,
                      &stats_.landmarks_pruned, &stats_.fast_differencings, &stats_.slow_differencings})
        *v = readU64(in);
    const auto ids = readIds(in, "flagged landmark");
    flagged_ = std::set<long>(ids.begin(), ids.end());
    last_seen_.clear();
    const size_t n = readSize(in, "landmark last seen");
    for (size_t i = 0; i < n; ++i)
    {
        const long id = readLong(in);
        last_seen_[id] = readDouble(in);
    }
    expectTag(in, "SlamMotionHook end");
}

}  // namespace hymm::dynamic
