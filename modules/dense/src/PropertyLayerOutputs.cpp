/**
 * @file PropertyLayerOutputs.cpp
 * @brief The property layer's outputs: property.gridmap and property_std.gridmap (MRPT
 *        CHeightGridMap2D), property_mean.png and property_std.png; its outline metrics
 *        score the centres of the cells with a value.
 */
#include "layer_outputs.h"

#include "hymm/core/serialized_file.h"
#include "hymm/dense/HybridMetricMap.h"
#include "hymm/dense/PropertyLayer.h"
#include "hymm/dense/map_images.h"

#include <mrpt/maps/CHeightGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>

namespace hymm::dense
{
namespace
{
// Property mean / std at the layer's cell size, as images and as MRPT height grids
// (h = mean or std, w = values fused; CHeightGridMap2D serialises h and w only, so the
// std gets a grid of its own).
struct PropertyMaps
{
    ScalarField mean, stddev;
    mrpt::maps::CHeightGridMap2D grid_mean, grid_std;
    size_t cells_with_value = 0;
    std::vector<Eigen::Vector2d> centres;  // of the grid cells with a value
};

PropertyMaps renderProperty(const LayerOutputContext& c)
{
    PropertyMaps p;
    const double res = c.map.options().property.cell_size_m;
    c.map.renderProperty(c.partition, res, p.mean, p.stddev);
    const Eigen::Vector2d hi = p.mean.origin + res * Eigen::Vector2d(p.mean.sizeX(), p.mean.sizeY());
    p.grid_mean.setSize(p.mean.origin.x(), hi.x(), p.mean.origin.y(), hi.y(), res);
    c.map.renderLayer(PropertyLayer::kKind, c.partition, p.grid_mean);
    p.grid_std = p.grid_mean;
    for (unsigned cy = 0; cy < p.grid_mean.getSizeY(); ++cy)
        for (unsigned cx = 0; cx < p.grid_mean.getSizeX(); ++cx)
        {
            const auto* cell = p.grid_mean.cellByIndex(cx, cy);
            if (!cell || cell->w == 0) continue;
            ++p.cells_with_value;
            p.centres.emplace_back(p.grid_mean.idx2x(cx), p.grid_mean.idx2y(cy));
            auto* s = p.grid_std.cellByIndex(cx, cy);
            s->h = s->u = cell->var;
        }
    return p;
}

// Colour range of a field's finite values ([0, 1] without any).
std::pair<double, double> valueRange(const ScalarField& f)
{
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (Eigen::Index i = 0; i < f.values.size(); ++i)
        if (std::isfinite(f.values(i))) lo = std::min(lo, f.values(i)), hi = std::max(hi, f.values(i));
    if (!(lo <= hi)) return {0.0, 1.0};
    if (hi - lo < 1e-9) return {lo - 0.5, hi + 0.5};
    return {lo, hi};
}

void writeProperty(const LayerOutputContext& c, const std::string& d, bool png)
{
    const PropertyMaps p = renderProperty(c);
    core::writeSerializedGz(p.grid_mean, d + "property.gridmap");
    core::writeSerializedGz(p.grid_std, d + "property_std.gridmap");
    if (!png) return;
    const auto [m_lo, m_hi] = valueRange(p.mean);
    saveScalarFieldPng(p.mean, d + "property_mean.png", m_lo, m_hi, &c.partition);
    const auto [s_lo, s_hi] = valueRange(p.stddev);
    saveScalarFieldPng(p.stddev, d + "property_std.png", std::min(0.0, s_lo), s_hi, &c.partition);
}

size_t propertyCells(const LayerOutputContext& c)
{
    const auto sizes = c.map.sizeByKind();
    const auto it = sizes.find(PropertyLayer::kKind);
    return it == sizes.end() ? 0 : it->second;
}

std::vector<LayerCounter> propertyCounts(const LayerOutputContext& c)
{
    const size_t cells = propertyCells(c);
    std::vector<LayerCounter> out = {
        {"cells", static_cast<unsigned long>(cells)},
        {"rendered_cells", static_cast<unsigned long>(renderProperty(c).cells_with_value)}};
    if (cells == 0 && c.returns_stored > 0)
        out.emplace_back("note", std::string("empty: the laser scans carry no values (intensities) to map"));
    return out;
}

std::vector<Eigen::Vector2d> propertyScored(const LayerOutputContext& c) { return renderProperty(c).centres; }

void describeProperty(std::ostream& f, const LayerOutputContext& c, size_t n)
{
    f << n << " cells with a value"
      << (n == 0 && c.returns_stored > 0 ? " (the scans carry no intensities)" : "");
}
}  // namespace

LayerOutputs propertyLayerOutputs()
{
    return {writeProperty, propertyCounts, propertyScored, describeProperty};
}

}  // namespace hymm::dense
