// The partition's state for a saved run (hymm-slam --save-state / --resume): regions with
// their reference and current vertices, the edge and landmark indices and the point
// grid with their id lists in their own order, and the next region id.
#include "hymm/ltr/RegionPartition.h"

#include <hymm/core/state_archive.h>

namespace hymm::ltr
{
using namespace hymm::core::state;

namespace
{
template <class Map, class WriteKey>
void writeIndex(mrpt::serialization::CArchive& out, const Map& m, const WriteKey& key)
{
    // Hash maps in key order: equal content, equal bytes. Only their lookups and sizes
    // matter to the partition (regionsInBox sorts what it collects).
    std::map<typename Map::key_type, const std::vector<long>*> sorted;
    for (const auto& [k, ids] : m) sorted.emplace(k, &ids);
    writeSize(out, sorted.size());
    for (const auto& [k, ids] : sorted)
    {
        key(k);
        writeIds(out, *ids);
    }
}
}  // namespace

void RegionPartition::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "RegionPartition");
    writeSize(out, regions_.size());
    for (const auto& [id, r] : regions_)
    {
        writeLong(out, r.id);
        for (long v : r.vertex_ids) writeLong(out, v);
        writeVertices(out, r.reference);
        writeVertices(out, r.current);
        out << r.creation_time;
    }
    writeSize(out, edges_.size());
    for (const auto& [e, ids] : edges_)
    {
        writeLong(out, e.first);
        writeLong(out, e.second);
        writeIds(out, ids);
    }
    writeIndex(out, by_landmark_, [&](long k) { writeLong(out, k); });
    writeIndex(out, grid_, [&](std::int64_t k) { out << k; });
    writeLong(out, next_id_);
}

void RegionPartition::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "RegionPartition");
    std::map<long, Region> regions;
    const size_t n = readSize(in, "region");
    for (size_t i = 0; i < n; ++i)
    {
        Region r;
        r.id = readLong(in);
        for (long& v : r.vertex_ids) v = readLong(in);
        readVertices(in, r.reference);
        readVertices(in, r.current);
        in >> r.creation_time;
        if (!regions.emplace(r.id, r).second)
            throw std::runtime_error("corrupt state: region " + std::to_string(r.id) + " twice");
    }
    std::map<EdgeKey, std::vector<long>> edges;
    const size_t ne = readSize(in, "edge");
    for (size_t i = 0; i < ne; ++i)
    {
        const long a = readLong(in), b = readLong(in);
        edges[{a, b}] = readIds(in, "edge region");
    }
    std::unordered_map<long, std::vector<long>> by_landmark;
    const size_t nl = readSize(in, "landmark index");
    for (size_t i = 0; i < nl; ++i)
    {
        const long k = readLong(in);
        by_landmark[k] = readIds(in, "landmark region");
    }
    std::unordered_map<std::int64_t, std::vector<long>> grid;
    const size_t ng = readSize(in, "grid cell");
    for (size_t i = 0; i < ng; ++i)
    {
        std::int64_t k = 0;
        in >> k;
        grid[k] = readIds(in, "grid region");
    }
    next_id_ = readLong(in);
    regions_ = std::move(regions);
    edges_ = std::move(edges);
    by_landmark_ = std::move(by_landmark);
    grid_ = std::move(grid);
}

}  // namespace hymm::ltr
