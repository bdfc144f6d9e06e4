// The hybrid map's state for a saved run (hymm-slam --save-state / --resume): the region
// maps and fallback tiles with every layer's state, the regions of the last scan and the
// scan counter; the classic grid; and the fallback tiles' text form for map.hymm.
#include "hymm/dense/ClassicOccupancyGrid.h"
#include "hymm/dense/HybridMetricMap.h"
#include "hymm/dense/LocalDenseMap.h"
#include "hymm/dense/OccupancyLayer.h"

#include <hymm/core/state_archive.h>

#include <istream>
#include <ostream>

namespace hymm::dense
{
using namespace hymm::core::state;
using Vertices = hymm::ltr::TriangleFrame::Vertices;

void LocalDenseMap::saveState(mrpt::serialization::CArchive& out) const
{
    writeLong(out, region_id_);
    writeVertices(out, reference_);
    writeSize(out, layers_.size());
    for (const auto& l : layers_)
    {
        out << l->kind();
        l->saveState(out);
    }
}

std::unique_ptr<LocalDenseMap> LocalDenseMap::loadState(mrpt::serialization::CArchive& in,
                                                        const LayerFactory& factory)
{
    const long id = readLong(in);
    Vertices ref;
    readVertices(in, ref);
    auto map = std::make_unique<LocalDenseMap>(id, ref);
    const size_t n = readSize(in, "layer");
    for (size_t i = 0; i < n; ++i)
    {
        std::string kind;
        in >> kind;
        auto layer = factory(kind, ref);
        if (!layer)
            throw std::runtime_error("state holds a dense layer '" + kind.substr(0, 40) +
                                     "' that the config does not enable");
        layer->loadState(in);
        map->addLayer(std::move(layer));
    }
    return map;
}

void HybridMetricMap::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "HybridMetricMap");
    writeSize(out, maps_.size());
    for (const auto& kv : maps_) kv.second->saveState(out);
    writeSize(out, fallback_.size());
    for (const auto& [key, map] : fallback_)
    {
        writeLong(out, key.anchor);
        out << static_cast<std::int32_t>(key.ix) << static_cast<std::int32_t>(key.iy)
            << static_cast<std::int32_t>(key.half);
        map->saveState(out);
    }
    writeIds(out, std::vector<long>(last_scan_regions_.begin(), last_scan_regions_.end()));
    out << static_cast<std::uint64_t>(scans_);
}

void HybridMetricMap::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "HybridMetricMap");
    const LocalDenseMap::LayerFactory factory = [this](const std::string& kind, const Vertices& ref) {
        return makeLayer(kind, ref);
    };
    std::map<long, std::unique_ptr<LocalDenseMap>> maps;
    const size_t n = readSize(in, "region map");
    for (size_t i = 0; i < n; ++i)
    {
        auto m = LocalDenseMap::loadState(in, factory);
        const long id = m->regionId();
        if (!maps.emplace(id, std::move(m)).second)
            throw std::runtime_error("corrupt state: region map " + std::to_string(id) + " twice");
    }
    std::map<FallbackTileKey, std::unique_ptr<LocalDenseMap>> fallback;
    const size_t nf = readSize(in, "fallback tile");
    for (size_t i = 0; i < nf; ++i)
    {
        FallbackTileKey key;
        std::int32_t ix = 0, iy = 0, half = 0;
        key.anchor = readLong(in);
        in >> ix >> iy >> half;
        key.ix = ix;
        key.iy = iy;
        key.half = half;
        fallback[key] = LocalDenseMap::loadState(in, factory);
    }
    const std::vector<long> last = readIds(in, "last scan region");
    scans_ = readU64(in);
    maps_ = std::move(maps);
    fallback_ = std::move(fallback);
    last_scan_regions_ = std::set<long>(last.begin(), last.end());
}

void ClassicOccupancyGrid::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "ClassicOccupancyGrid");
    grid_.saveState(out);
}
void ClassicOccupancyGrid::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "ClassicOccupancyGrid");
    grid_.loadState(in);
}

// --- fallback tiles as text (map.hymm, CHybridMetricMap version 1) -----------------------
void HybridMetricMap::saveFallbackTiles(std::ostream& out) const
{
    out << "fallback_tiles " << fallback_.size() << '\n';
    for (const auto& [key, map] : fallback_)
    {
        out << "tile " << key.anchor << ' ' << key.ix << ' ' << key.iy << ' ' << key.half << '\n';
        map->save(out);
    }
}

void HybridMetricMap::loadFallbackTiles(std::istream& in)
{
    std::string tag;
    size_t n = 0;
    if (!(in >> tag >> n) || tag != "fallback_tiles")
        throw std::runtime_error("HybridMetricMap::loadFallbackTiles: expected 'fallback_tiles <count>'");
    const LocalDenseMap::LayerFactory factory = [this](const std::string& kind, const Vertices& ref) {
        return makeLayer(kind, ref);
    };
    std::map<FallbackTileKey, std::unique_ptr<LocalDenseMap>> tiles;
    for (size_t i = 0; i < n; ++i)
    {
        FallbackTileKey key;
        if (!(in >> tag >> key.anchor >> key.ix >> key.iy >> key.half) || tag != "tile" ||
            (key.half != 0 && key.half != 1))
            throw std::runtime_error("HybridMetricMap::loadFallbackTiles: bad tile " + std::to_string(i));
        auto map = LocalDenseMap::load(in, factory);
        if (map->regionId() != key.anchor)
            throw std::runtime_error("HybridMetricMap::loadFallbackTiles: tile " + std::to_string(i) +
                                     " names anchor " + std::to_string(map->regionId()));
        // As fallbackMapFor(): overlapping tiles each draw what they observed.
        if (auto* occ = dynamic_cast<OccupancyLayer*>(map->layer(OccupancyLayer::kKind)))
            occ->setRenderMode(OccupancyLayer::RenderMode::MaxObserved);
        if (!tiles.emplace(key, std::move(map)).second)
            throw std::runtime_error("HybridMetricMap::loadFallbackTiles: tile " + std::to_string(i) + " twice");
    }
    fallback_ = std::move(tiles);
    // As localMapFor() with the fallback on: a region does not hide what a tile under it
    // saw (text save() does not keep the render mode).
    if (options_.fallback_max_distance_m > 0)
        for (auto& kv : maps_)
            if (auto* occ = dynamic_cast<OccupancyLayer*>(kv.second->layer(OccupancyLayer::kKind)))
                occ->setRenderMode(OccupancyLayer::RenderMode::MaxObserved);
}

}  // namespace hymm::dense
