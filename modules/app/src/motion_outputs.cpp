#include "hymm/app/motion_outputs.h"

#include <hymm/dense/ScalarField.h>
#include <hymm/dense/geometry.h>
#include <hymm/dense/OccupancyLayer.h>
#include <hymm/dense/map_images.h>
#include <hymm/sim/motion_truth.h>

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

namespace hymm::app
{
using dynamic::MotionKind;

MotionTruth motionTruthFromWorld(const sim::World& world, double t0, double t1, double dt)
{
    MotionTruth t;
    for (const auto& o : world.objects())
    {
        if (o.isStatic())
        {
            const auto poly = o.outlineAt(t0);
            t.static_outlines.emplace_back(poly.begin(), poly.end());
            continue;
        }
        auto& fp = t.moving[o.name.empty() ? "object_" + std::to_string(o.id) : o.name];
        const long n = static_cast<long>(std::floor((t1 - t0) / dt + 1e-9));
        for (long k = 0; k <= n; ++k)
        {
            const double tk = t0 + static_cast<double>(k) * dt;
            if (!o.presentAt(tk)) continue;
            const auto poly = o.outlineAt(tk);
            // A still stretch gives the same footprint again and again: keep one.
            if (!fp.empty() && (fp.back()[0] - poly[0]).norm() < 1e-9 && (fp.back()[1] - poly[1]).norm() < 1e-9)
                continue;
            fp.emplace_back(poly.begin(), poly.end());
        }
    }
    // Landmark trunks are static outlines too (their contours flicker like walls).
    for (const auto& l : world.landmarks())
        t.static_outlines.push_back(dense::circlePolygon(l.position, l.radius, 16));
    return t;
}

MotionTruth motionTruthFromRecords(const std::vector<sim::ObjectOutlineRecord>& records)
{
    MotionTruth t;
    if (records.empty()) return t;
    double first = std::numeric_limits<double>::infinity(), last = -first;
    std::map<long, std::vector<const sim::ObjectOutlineRecord*>> by_id;
    for (const auto& r : records)
    {
        first = std::min(first, r.t_from);
        last = std::max(last, r.t_to);
        by_id[r.id].push_back(&r);
    }
    for (const auto& [id, rs] : by_id)
    {
        const bool is_static = rs.size() == 1 && rs[0]->t_from <= first + 1e-6 && rs[0]->t_to >= last - 1e-6;
        if (is_static)
            t.static_outlines.emplace_back(rs[0]->outline.begin(), rs[0]->outline.end());
        else
            for (const auto* r : rs)
                t.moving["object_" + std::to_string(id)].emplace_back(r->outline.begin(), r->outline.end());
    }
    return t;
}

MotionRaster rasterMotionLayer(const DenseSlam& slam, MotionKind kind, double resolution)
{
    const auto* hook = slam.motionHook();
    if (!hook || !slam.partition() || !slam.hybridMap())
        throw std::logic_error("rasterMotionLayer: the run has no motion layers");
    mrpt::maps::COccupancyGridMap2D grid;
    slam.hybridMap()->renderOccupancy(*slam.partition(), resolution, grid);
    MotionRaster r;
    r.covered = eval::CellMask::like(grid);
    const auto& p = *slam.partition();
    const auto cover = [&](const ltr::TriangleFrame::Vertices& cur) {
        Eigen::Vector2d lo = cur[0].cwiseMin(cur[1]).cwiseMin(cur[2]), hi = cur[0].cwiseMax(cur[1]).cwiseMax(cur[2]);
        int x0, y0, x1, y1;
        r.covered.cellOf(lo, x0, y0);
        r.covered.cellOf(hi, x1, y1);
        for (int iy = std::max(0, y0); iy <= std::min(r.covered.ny - 1, y1); ++iy)
            for (int ix = std::max(0, x0); ix <= std::min(r.covered.nx - 1, x1); ++ix)
                if (dense::triangleContains(cur, r.covered.centre(ix, iy), 1e-9)) r.covered.set(ix, iy);
    };
    for (long id : slam.hybridMap()->regionIds())
        if (p.has(id)) cover(p.region(id).current);
    // The fallback tiles that hold occupancy: the motion layers read them where no region
    // holds a place ([MotionDetector] fallback_tiles; without it nothing marks them).
    const auto& hybrid = *slam.hybridMap();
    for (const auto& key : hybrid.fallbackTileKeys())
    {
        const auto* tile = hybrid.fallbackMap(key);
        if (!tile || !tile->layer(dense::OccupancyLayer::kKind)) continue;
        const auto to_current = hybrid.fallbackToCurrent(p, key.anchor);
        if (!to_current) continue;
        cover(dense::currentFallbackTileTriangle(key, hybrid.options().fallback_tile_m, *to_current));
    }
    // The layer alone: a blank grid of the same geometry, marked cells at 1.
    mrpt::maps::COccupancyGridMap2D layer(grid.getXMin(), grid.getXMax(), grid.getYMin(), grid.getYMax(),
                                          grid.getResolution());
    layer.fill(0.0f);
    hook->detector().renderInto(kind, p, layer);
    r.marked = eval::CellMask::fromGrid(layer, 0.99f);
    return r;
}

eval::DetectionScore scoreAgainst(const MotionRaster& raster, const eval::CellMask& truth, int tolerance)
{
    return eval::scoreDetection(raster.marked, truth.intersect(raster.covered), tolerance);
}

MotionScore scoreMotionLayer(const DenseSlam& slam, MotionKind kind, const MotionTruth& truth,
                             double resolution, int tolerance)
{
    const MotionRaster r = rasterMotionLayer(slam, kind, resolution);
    MotionScore s;
    s.covered_cells = r.covered.count();
    eval::CellMask empty = r.covered;
    std::fill(empty.bits.begin(), empty.bits.end(), std::uint8_t{0});
    eval::CellMask all = empty;
    for (const auto& [name, polys] : truth.moving)
    {
        eval::CellMask m = empty;
        for (const auto& poly : polys) m.fillPolygon(poly);
        // Thin objects: their cells are the band around the outline too.
        for (const auto& poly : polys) m.markOutline(poly, 0.5 * resolution);
        s.per_object[name] = scoreAgainst(r, m, tolerance);
        all = all.unite(m);
    }
    s.total = scoreAgainst(r, all, tolerance);
    eval::CellMask st = r.covered;
    std::fill(st.bits.begin(), st.bits.end(), std::uint8_t{0});
    for (const auto& poly : truth.static_outlines) st.markOutline(poly, 0.5 * resolution);
    st = st.intersect(r.covered).minus(all.dilated(tolerance));
    s.static_cells = st.count();
    s.static_marked = r.marked.intersect(st).count();
    s.static_fp_fraction =
        s.static_cells ? static_cast<double>(s.static_marked) / static_cast<double>(s.static_cells) : 0.0;
    return s;
}

void writeMotionMetrics(eval::MetricsJson& j, const DenseSlam& slam, const MotionTruth& truth)
{
    const auto* hook = slam.motionHook();
    if (!hook || !slam.hybridMap()) return;
    const double res = slam.hybridMap()->options().occupancy.cell_size_m;
    const auto& st = hook->stats();
    j.set("dynamic.creations_blocked", st.creations_blocked);
    j.set("dynamic.landmarks_flagged", st.landmarks_flagged);
    j.set("dynamic.landmarks_pruned", st.landmarks_pruned);
    j.set("dynamic.fast.differencings", st.fast_differencings);
    j.set("dynamic.slow.differencings", st.slow_differencings);
    const auto& det = hook->detector().options();
    for (auto kind : {MotionKind::Fast, MotionKind::Slow})
    {
        if (!(kind == MotionKind::Fast ? det.enable_fast : det.enable_slow)) continue;
        const std::string k = std::string("dynamic.") + dynamic::motionKindName(kind);
        const auto s = scoreMotionLayer(slam, kind, truth, res, 1);
        j.set(k + ".precision", s.total.precision);
        j.set(k + ".recall", s.total.recall);
        j.set(k + ".cells", s.total.detected);
        j.set(k + ".static_fp_fraction", s.static_fp_fraction);
        for (const auto& [name, sc] : s.per_object)
        {
            j.set(k + ".object." + name + ".recall", sc.recall);
            j.set(k + ".object." + name + ".detected", sc.truth_found > 0);
        }
    }
}

namespace
{
dense::ScalarField fieldOf(const dynamic::Difference& d, const std::vector<float>& v)
{
    dense::ScalarField f;
    f.resolution = 1.0;
    f.values.resize(d.ny, d.nx);
    for (int iy = 0; iy < d.ny; ++iy)
        for (int ix = 0; ix < d.nx; ++ix)
            f.values(iy, ix) = v[static_cast<size_t>(iy) * static_cast<size_t>(d.nx) + static_cast<size_t>(ix)];
    return f;
}
}  // namespace

void writeMotionOutputs(const DenseSlam& slam, const std::string& dir, bool png)
{
    const auto* hook = slam.motionHook();
    if (!hook || !slam.hybridMap() || !png) return;
    const std::string d = dir.empty() || dir.back() == '/' ? dir : dir + "/";
    const auto& p = *slam.partition();
    const double res = slam.hybridMap()->options().occupancy.cell_size_m;
    const auto& det = hook->detector().options();
    for (auto kind : {MotionKind::Fast, MotionKind::Slow})
    {
        if (!(kind == MotionKind::Fast ? det.enable_fast : det.enable_slow)) continue;
        const std::string name = dynamic::motionKindName(kind);
        mrpt::maps::COccupancyGridMap2D grid;
        slam.hybridMap()->renderOccupancy(p, res, grid);
        // Occupancy in light grey, motion cells black.
        for (unsigned y = 0; y < grid.getSizeY(); ++y)
            for (unsigned x = 0; x < grid.getSizeX(); ++x) grid.setCell(x, y, 0.3f * grid.getCell(x, y));
        hook->detector().renderInto(kind, p, grid);
        dense::saveOccupancyPng(grid, d + "motion_" + name + ".png", &p);
        const auto& last = hook->detector().lastDifference(kind);
        if (last.region >= 0)
        {
            dense::saveScalarFieldPng(fieldOf(last.diff, last.diff.raw), d + "motion_" + name + "_raw.png", 0.0, 1.0);
            dense::saveScalarFieldPng(fieldOf(last.diff, last.diff.filtered),
                                      d + "motion_" + name + "_filtered.png", 0.0, 1.0);
        }
    }
    mrpt::maps::COccupancyGridMap2D stat;
    hook->detector().renderStaticOccupancy(*slam.hybridMap(), p, res, stat);
    dense::saveOccupancyPng(stat, d + "occupancy_static.png", &p);
}

}  // namespace hymm::app
