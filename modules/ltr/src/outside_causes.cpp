#include "hymm/ltr/outside_causes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace hymm::ltr
{
namespace
{
double cross(const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); }

bool inside(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
            bool closed)
{
    const double d1 = cross(b - a, p - a), d2 = cross(c - b, p - b), d3 = cross(a - c, p - c);
    if (closed)
        return (d1 >= 0 && d2 >= 0 && d3 >= 0) || (d1 <= 0 && d2 <= 0 && d3 <= 0);
    return (d1 > 0 && d2 > 0 && d3 > 0) || (d1 < 0 && d2 < 0 && d3 < 0);
}

OutsideCause causeOf(BaseCondition c)
{
    switch (c)
    {
        case BaseCondition::LongEdge: return OutsideCause::LongEdge;
        case BaseCondition::LowVertexCorrelation:
        case BaseCondition::LowVehicleCorrelation: return OutsideCause::Correlation;
        case BaseCondition::Overlap: return OutsideCause::Overlap;
        case BaseCondition::Accepted: return OutsideCause::NotGrown;
        default: return OutsideCause::Shape;
    }
}
}  // namespace

const char* toString(OutsideCause c)
{
    switch (c)
    {
        case OutsideCause::InRegionNow: return "in_region_now";
        case OutsideCause::NoLandmarkTriangle: return "no_landmark_triangle";
        case OutsideCause::LongEdge: return "long_edge";
        case OutsideCause::Shape: return "shape";
        case OutsideCause::Correlation: return "correlation";
        case OutsideCause::Overlap: return "overlap";
        case OutsideCause::NotGrown: return "not_grown";
        default: return "unknown";
    }
}

size_t OutsideCauseCounts::total() const { return std::accumulate(n.begin(), n.end(), size_t{0}); }

OutsideCause classifyOutsideReturn(
    const RegionPartition& partition, const LandmarkCovarianceView& view, const Eigen::Vector2d& p, int nearest)
{
    if (partition.findRegion(p)) return OutsideCause::InRegionNow;
    const double reach = partition.options().conditions.max_edge_length_m;
    std::vector<std::pair<double, long>> near;
    for (const long id : view.idsNear(p, reach))
        if (!view.isVirtual(id)) near.emplace_back((view.mean(id) - p).norm(), id);
    std::sort(near.begin(), near.end());
    if (near.size() > static_cast<size_t>(std::max(3, nearest))) near.resize(static_cast<size_t>(std::max(3, nearest)));
    const size_t k = near.size();
    std::vector<Eigen::Vector2d> pos(k);
    for (size_t i = 0; i < k; ++i) pos[i] = view.mean(near[i].second);

    // The Delaunay-like triangle there: containing p, empty of the other nearby landmarks,
    // shortest longest edge.
    std::array<long, 3> best{{-1, -1, -1}};
    double best_edge = std::numeric_limits<double>::infinity();
    for (size_t a = 0; a < k; ++a)
        for (size_t b = a + 1; b < k; ++b)
            for (size_t c = b + 1; c < k; ++c)
            {
                if (!inside(p, pos[a], pos[b], pos[c], true)) continue;
                bool empty = true;
                for (size_t o = 0; o < k && empty; ++o)
                    if (o != a && o != b && o != c && inside(pos[o], pos[a], pos[b], pos[c], false)) empty = false;
                if (!empty) continue;
                const double e = std::max({(pos[a] - pos[b]).norm(), (pos[b] - pos[c]).norm(), (pos[c] - pos[a]).norm()});
                if (e < best_edge)
                {
                    best_edge = e;
                    best = {near[a].second, near[b].second, near[c].second};
                }
            }
    if (best[0] < 0) return OutsideCause::NoLandmarkTriangle;

    std::vector<TriangleFrame::Vertices> existing;
    TriangleFrame::Vertices tri{view.mean(best[0]), view.mean(best[1]), view.mean(best[2])};
    const Eigen::Vector2d lo = tri[0].cwiseMin(tri[1]).cwiseMin(tri[2]), hi = tri[0].cwiseMax(tri[1]).cwiseMax(tri[2]);
    for (const long id : partition.regionsInBox(lo, hi)) existing.push_back(partition.region(id).current);
    return causeOf(partition.checker().check(best, view, existing).reason);
}

}  // namespace hymm::ltr
