// Global rendering of the SOG and property layers and per-kind statistics
// (HybridMetricMap.h); kept apart from the fusion code of HybridMetricMap.cpp.
#include "hymm/dense/HybridMetricMap.h"

#include <limits>
#include <stdexcept>

namespace hymm::dense
{
using hymm::ltr::AffineRegionMap;
using hymm::ltr::RegionPartition;

bool HybridMetricMap::layerBox(
    const std::string& kind, const RegionPartition& partition, Eigen::Vector2d& lo, Eigen::Vector2d& hi,
    Content content) const
{
    lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    hi = -lo;
    forEachMap(partition, content, [&](const LocalDenseMap& map, const AffineRegionMap& to_current) {
        if (!map.layer(kind)) return;
        for (const auto& v : map.reference())
        {
            const Eigen::Vector2d c = to_current.mapPoint(v);
            lo = lo.cwiseMin(c);
            hi = hi.cwiseMax(c);
        }
    });
    return lo.x() <= hi.x();
}

void HybridMetricMap::renderSogSurface(
    const RegionPartition& partition, double resolution_m, ScalarField& out, double margin_m) const
{
    if (!(resolution_m > 0) || !(margin_m >= 0))
        throw std::invalid_argument("HybridMetricMap::renderSogSurface: need resolution > 0 and margin >= 0");
    core::TimedSection tle(profiler_, "dense.render.sog_surface");
    Eigen::Vector2d lo, hi;
    if (!layerBox(SogLayer::kKind, partition, lo, hi)) lo = hi = Eigen::Vector2d::Zero();
    const Eigen::Vector2d m = Eigen::Vector2d::Constant(margin_m);
    out = ScalarField::covering(lo - m, hi + m, resolution_m, 0.0);
    forEachMap(partition, Content::All, [&](const LocalDenseMap& map, const AffineRegionMap& to_current) {
        if (const auto* sog = map.layerAs<SogLayer>(SogLayer::kKind)) sog->addSurface(to_current, out);
    });
}

std::vector<std::vector<Eigen::Vector2d>> HybridMetricMap::renderSogEllipses(
    const RegionPartition& partition, int points) const
{
    std::vector<std::vector<Eigen::Vector2d>> out;
    forEachMap(partition, Content::All, [&](const LocalDenseMap& map, const AffineRegionMap& to_current) {
        if (const auto* sog = map.layerAs<SogLayer>(SogLayer::kKind))
        {
            auto e = sog->ellipses(to_current, points);
            out.insert(out.end(), std::make_move_iterator(e.begin()), std::make_move_iterator(e.end()));
        }
    });
    return out;
}

void HybridMetricMap::renderProperty(
    const RegionPartition& partition, double resolution_m, ScalarField& mean, ScalarField& stddev) const
{
    if (!(resolution_m > 0)) throw std::invalid_argument("HybridMetricMap::renderProperty: resolution must be > 0");
    core::TimedSection tle(profiler_, "dense.render.property");
    Eigen::Vector2d lo, hi;
    if (!layerBox(PropertyLayer::kKind, partition, lo, hi)) lo = hi = Eigen::Vector2d::Zero();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    mean = ScalarField::covering(lo, hi, resolution_m, nan);
    stddev = ScalarField::covering(lo, hi, resolution_m, nan);
    forEachMap(partition, Content::All, [&](const LocalDenseMap& map, const AffineRegionMap& to_current) {
        if (const auto* prop = map.layerAs<PropertyLayer>(PropertyLayer::kKind))
            prop->renderFields(to_current, mean, &stddev);
    });
}

std::vector<mrpt::poses::CPoint2DPDFGaussian> HybridMetricMap::renderSogGaussians(
    const RegionPartition& partition, Content content) const
{
    std::vector<mrpt::poses::CPoint2DPDFGaussian> out;
    forEachMap(partition, content, [&](const LocalDenseMap& map, const AffineRegionMap& to_current) {
        if (const auto* sog = map.layerAs<SogLayer>(SogLayer::kKind))
            for (size_t i = 0; i < sog->size(); ++i) out.push_back(sog->gaussianAt(i, to_current));
    });
    return out;
}

std::map<std::string, size_t> HybridMetricMap::sizeByKind() const
{
    std::map<std::string, size_t> out;
    for (const auto& kv : maps_)
        for (const std::string& kind : kv.second->layerKinds())
            out[kind] += kv.second->layer(kind)->size();
    for (const auto& kv : fallback_)
        for (const std::string& kind : kv.second->layerKinds())
            out[kind] += kv.second->layer(kind)->size();
    return out;
}

std::vector<HybridMetricMap::OccupancyRegionStats> HybridMetricMap::occupancyRegionStats(
    double occupied_prob) const
{
    if (!(occupied_prob > 0 && occupied_prob < 1))
        throw std::invalid_argument(
            "HybridMetricMap::occupancyRegionStats: occupied_prob must be in (0, 1)");
    const double l_occ = logit(occupied_prob);
    const double l_free = logit(options_.occupancy.coarsen_min_prob);
    std::vector<OccupancyRegionStats> out;
    for (const auto& [id, map] : maps_)
    {
        const auto* occ = map->layerAs<OccupancyLayer>(OccupancyLayer::kKind);
        if (!occ) continue;
        OccupancyRegionStats r;
        r.id = id;
        r.coarse = occ->isCoarse();
        r.memory_bytes = occ->memoryBytes();
        const LogOddsGrid& g = occ->grid();
        r.cell_size_m = g.cellSize();
        for (int iy = 0; iy < g.sizeY(); ++iy)
            for (int ix = 0; ix < g.sizeX(); ++ix)
            {
                if (!g.updatable(ix, iy)) continue;  // outside the triangle: a neighbour's
                ++r.cells;
                const double l = g.logOdds(ix, iy);
                if (l > l_occ) ++r.occupied;
                if (l < l_free) ++r.free;
            }
        out.push_back(r);
    }
    return out;
}

}  // namespace hymm::dense
