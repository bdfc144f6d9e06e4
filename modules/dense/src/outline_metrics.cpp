#include "hymm/dense/outline_metrics.h"

#include "hymm/dense/geometry.h"

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CPointsMap.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace hymm::dense
{
namespace
{
using Segment = std::pair<Eigen::Vector2d, Eigen::Vector2d>;

std::vector<Segment> segmentsOf(const std::vector<Polygon>& outlines, bool closed)
{
    std::vector<Segment> out;
    for (const Polygon& poly : outlines)
    {
        const size_t n = poly.size();
        if (n < 2) continue;
        const size_t edges = closed && n > 2 ? n : n - 1;
        for (size_t i = 0; i < edges; ++i) out.emplace_back(poly[i], poly[(i + 1) % n]);
    }
    return out;
}

/** Uniform hash grid of points, cell = query radius: a query visits 3x3 cells. */
class PointHash
{
public:
    PointHash(const std::vector<Eigen::Vector2d>& pts, double cell) : pts_(pts), cell_(cell)
    {
        for (size_t i = 0; i < pts.size(); ++i) cells_[key(pts[i])].push_back(i);
    }
    bool anyWithin(const Eigen::Vector2d& q, double r) const
    {
        const std::int64_t cx = coord(q.x()), cy = coord(q.y());
        for (std::int64_t dx = -1; dx <= 1; ++dx)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
            {
                const auto it = cells_.find(packCellKey(cx + dx, cy + dy));
                if (it == cells_.end()) continue;
                for (const size_t i : it->second)
                    if ((pts_[i] - q).squaredNorm() <= r * r) return true;
            }
        return false;
    }

private:
    std::int64_t coord(double v) const { return static_cast<std::int64_t>(std::floor(v / cell_)); }
    std::int64_t key(const Eigen::Vector2d& p) const { return packCellKey(coord(p.x()), coord(p.y())); }

    const std::vector<Eigen::Vector2d>& pts_;
    double cell_;
    std::unordered_map<std::int64_t, std::vector<size_t>> cells_;
};
}  // namespace

Polygon circlePolygon(const Eigen::Vector2d& centre, double radius, int sides)
{
    if (!(radius > 0)) return {centre, centre};
    Polygon p;
    for (int k = 0; k < sides; ++k)
    {
        const double a = 2 * M_PI * k / sides;
        p.emplace_back(centre + radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
    return p;
}

OutlineMetrics evaluateOutlines(
    const std::vector<Eigen::Vector2d>& points, const std::vector<Polygon>& outlines,
    const OutlineMetricsOptions& options)
{
    if (!(options.sample_step_m > 0) || !(options.coverage_radius_m > 0))
        throw std::invalid_argument("evaluateOutlines: sample_step_m and coverage_radius_m must be > 0");
    const std::vector<Segment> segs = segmentsOf(outlines, options.closed);
    if (segs.empty()) throw std::invalid_argument("evaluateOutlines: no outline segment");

    OutlineMetrics m;
    m.points = points.size();
    // Accuracy.
    std::vector<double> d;
    d.reserve(points.size());
    for (const auto& p : points)
    {
        double best = std::numeric_limits<double>::infinity();
        for (const auto& s : segs) best = std::min(best, distanceToSegment(p, s.first, s.second));
        d.push_back(best);
    }
    if (d.empty())
        m.mean_distance_m = m.p95_distance_m = std::numeric_limits<double>::quiet_NaN();
    else
    {
        double sum = 0;
        for (const double v : d) sum += v;
        m.mean_distance_m = sum / static_cast<double>(d.size());
        const size_t rank = static_cast<size_t>(std::ceil(0.95 * static_cast<double>(d.size())));
        std::nth_element(d.begin(), d.begin() + static_cast<long>(rank - 1), d.end());
        m.p95_distance_m = d[rank - 1];
    }
    // Coverage: samples at s = 0, step, 2 step, ... < length on each segment (the
    // next segment starts at the shared vertex); an open polyline adds its end point.
    const PointHash hash(points, options.coverage_radius_m);
    const auto sample = [&](const Eigen::Vector2d& q) {
        ++m.outline_samples;
        if (hash.anyWithin(q, options.coverage_radius_m)) ++m.covered_samples;
    };
    for (const auto& s : segs)
    {
        const double len = (s.second - s.first).norm();
        const auto n = static_cast<size_t>(std::ceil(len / options.sample_step_m - 1e-9));
        for (size_t k = 0; k < n; ++k)
            sample(s.first + (s.second - s.first) * (static_cast<double>(k) * options.sample_step_m / len));
    }
    if (!options.closed)
        for (const Polygon& poly : outlines)
            if (poly.size() >= 2) sample(poly.back());
    m.coverage = m.outline_samples ? static_cast<double>(m.covered_samples) / static_cast<double>(m.outline_samples) : 0.0;
    return m;
}

std::vector<Eigen::Vector2d> pointsOf(const mrpt::maps::CPointsMap& map)
{
    std::vector<Eigen::Vector2d> out;
    out.reserve(map.size());
    const auto& xs = map.getPointsBufferRef_x();
    const auto& ys = map.getPointsBufferRef_y();
    for (size_t i = 0; i < xs.size(); ++i) out.emplace_back(xs[i], ys[i]);
    return out;
}

std::vector<Eigen::Vector2d> occupiedCellCentres(
    const mrpt::maps::COccupancyGridMap2D& grid, double min_probability)
{
    std::vector<Eigen::Vector2d> out;
    for (unsigned cy = 0; cy < grid.getSizeY(); ++cy)
        for (unsigned cx = 0; cx < grid.getSizeX(); ++cx)
            if (grid.getCell(static_cast<int>(cx), static_cast<int>(cy)) > min_probability)
                out.emplace_back(grid.idx2x(cx), grid.idx2y(cy));
    return out;
}

}  // namespace hymm::dense
