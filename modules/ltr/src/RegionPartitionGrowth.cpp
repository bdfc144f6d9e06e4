/**
 * @file RegionPartitionGrowth.cpp
 * @brief Growth of the LTR partition around the vehicle (thesis Sec. 3.5, Fig. 3.1).
 */
#include "hymm/ltr/RegionPartition.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace hymm::ltr
{
namespace
{
// Third-vertex candidates tried per boundary edge, best (largest angle) first. The
// best one is the Delaunay choice; a few more let an edge grow when that one fails a
// condition, without falling back to long, thin triangles (those fail min_angle).
constexpr int kMaxCandidatesPerEdge = 4;
// A landmark counts as inside a candidate only if it is this far inside in
// barycentric units, so that vertices and points on shared edges do not block.
constexpr double kInsideMargin = 1e-9;

double cross(const Eigen::Vector2d& u, const Eigen::Vector2d& v)
{
    return u.x() * v.y() - u.y() * v.x();
}

/** > 0 if d lies strictly inside the circumcircle of (a, b, c), any orientation. */
double inCircle(
    const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
    const Eigen::Vector2d& d)
{
    Eigen::Matrix3d m;
    for (int r = 0; r < 3; ++r)
    {
        const Eigen::Vector2d p = (r == 0 ? a : r == 1 ? b : c) - d;
        m.row(r) << p.x(), p.y(), p.squaredNorm();
    }
    const double orient = cross(b - a, c - a);
    return orient > 0 ? m.determinant() : -m.determinant();
}

/** Third vertices for free edge (a, b) among `eligible`, on the side away from the owning
 *  region's third vertex `inner`, by decreasing angle subtended by the edge (with the
 *  angle). At most one virtual vertex per region (virtual-virtual correlations are not
 *  kept). */
std::vector<std::pair<double, long>> thirdVertices(const LandmarkCovarianceView& view,
                                                   const std::vector<long>& eligible, long a, long b,
                                                   long inner)
{
    const Eigen::Vector2d pa = view.mean(a), pb = view.mean(b);
    const double inner_side = cross(pb - pa, view.mean(inner) - pa);
    std::vector<std::pair<double, long>> cands;
    const bool edge_has_virtual = view.isVirtual(a) || view.isVirtual(b);
    for (const long c : eligible)
    {
        if (c == a || c == b) continue;
        if (edge_has_virtual && view.isVirtual(c)) continue;
        const Eigen::Vector2d pc = view.mean(c);
        if (!(cross(pb - pa, pc - pa) * inner_side < 0)) continue;
        const Eigen::Vector2d u = pa - pc, v = pb - pc;
        cands.emplace_back(std::atan2(std::abs(cross(u, v)), u.dot(v)), c);
    }
    std::sort(cands.begin(), cands.end(), [](const auto& x, const auto& y) {
        return x.first > y.first || (x.first == y.first && x.second < y.second);
    });
    return cands;
}
}  // namespace

struct RegionPartition::Neighbourhood
{
    Eigen::Vector2d vehicle;
    std::vector<long> nearby;    //!< landmarks within search_radius_m of the vehicle
    std::vector<long> eligible;  //!< nearby and correlated enough with the vehicle,
                                 //!< sorted by distance to the vehicle
    std::unordered_set<long> nearby_set;
};

std::vector<long> RegionPartition::update(const LandmarkCovarianceView& view, double time)
{
    // 1. Bring the lookup grid to today's vertex estimates.
    updateVertexPositions(view);
    return grow(view, time);
}

std::vector<long> RegionPartition::grow(const LandmarkCovarianceView& view, double time)
{
    // 2. Landmarks around the vehicle that may become vertices. The vehicle
    //    correlation depends on one landmark only, so it is filtered here once.
    Neighbourhood nb;
    nb.vehicle = view.vehiclePose().head<2>();
    for (const long id : view.idsNear(nb.vehicle, options_.search_radius_m))
    {
        nb.nearby.push_back(id);
        nb.nearby_set.insert(id);
        if (options_.conditions.min_vehicle_correlation <= 0 ||
            checker_.vehicleCorrelation(id, view) >= options_.conditions.min_vehicle_correlation)
            nb.eligible.push_back(id);
    }
    std::sort(nb.eligible.begin(), nb.eligible.end(), [&](long a, long b) {
        return (view.mean(a) - nb.vehicle).squaredNorm() < (view.mean(b) - nb.vehicle).squaredNorm();
    });

    // 3. Grow from the free edges of existing regions first; seed only when no edge
    //    can grow, so that the covered area stays connected where possible.
    std::vector<long> created;
    std::vector<EdgeKey> failed_edges;
    while (static_cast<int>(created.size()) < options_.max_new_regions_per_update)
    {
        if (growFromEdges(view, nb, time, failed_edges, created)) continue;
        if (seed(view, nb, time, created)) continue;
        break;
    }
    return created;
}

bool RegionPartition::containsOtherLandmark(
    const TriangleFrame::Vertices& tri, const std::array<long, 3>& ids,
    const LandmarkCovarianceView& view, const std::vector<long>& nearby) const
{
    const auto frame = TriangleFrame::tryCreate(tri);
    if (!frame) return false;  // the checker reports the degenerate triangle
    for (const long m : nearby)
    {
        if (m == ids[0] || m == ids[1] || m == ids[2]) continue;
        const Eigen::Vector2d l = frame->toLocal(view.mean(m));
        if (l.x() > kInsideMargin && l.y() > kInsideMargin && l.x() + l.y() < 1 - kInsideMargin)
            return true;
    }
    return false;
}

bool RegionPartition::growFromEdges(
    const LandmarkCovarianceView& view, const Neighbourhood& nb, double time,
    std::vector<EdgeKey>& failed_edges, std::vector<long>& created)
{
    // Free edges (used by one region) with both ends near the vehicle; the grid
    // limits the search to regions around the vehicle.
    struct FreeEdge
    {
        EdgeKey key;
        long inner;  // third vertex of the region that owns the edge
        double dist;
    };
    std::vector<FreeEdge> free_edges;
    const Eigen::Vector2d r = Eigen::Vector2d::Constant(options_.search_radius_m);
    for (const long rid : regionsInBox(nb.vehicle - r, nb.vehicle + r))
    {
        const Region& reg = regions_.at(rid);
        for (size_t k = 0; k < 3; ++k)
        {
            const long a = reg.vertex_ids[k], b = reg.vertex_ids[(k + 1) % 3];
            const EdgeKey key = edgeKey(a, b);
            if (edges_.at(key).size() != 1 || !nb.nearby_set.count(a) || !nb.nearby_set.count(b))
                continue;
            if (std::find(failed_edges.begin(), failed_edges.end(), key) != failed_edges.end())
                continue;
            const double d = (0.5 * (view.mean(a) + view.mean(b)) - nb.vehicle).norm();
            free_edges.push_back({key, reg.vertex_ids[(k + 2) % 3], d});
        }
    }
    std::sort(free_edges.begin(), free_edges.end(), [](const FreeEdge& x, const FreeEdge& y) {
        return x.dist < y.dist || (x.dist == y.dist && x.key < y.key);
    });

    for (const FreeEdge& e : free_edges)
    {
        const long a = e.key.first, b = e.key.second;
        const Eigen::Vector2d pa = view.mean(a), pb = view.mean(b);
        const auto cands = thirdVertices(view, nb.eligible, a, b, e.inner);
        int tries = 0;
        for (const auto& [angle, c] : cands)
        {
            if (tries >= kMaxCandidatesPerEdge) break;
            const std::array<long, 3> ids{a, b, c};
            if (containsOtherLandmark({pa, pb, view.mean(c)}, ids, view, nb.nearby)) continue;
            ++tries;
            long id = -1;
            if (tryAddRegion(ids, view, time, &id).accepted())
            {
                created.push_back(id);
                return true;
            }
        }
        failed_edges.push_back(e.key);
    }
    return false;
}

bool RegionPartition::seed(
    const LandmarkCovarianceView& view, const Neighbourhood& nb, double time,
    std::vector<long>& created)
{
    const size_t n =
        std::min(nb.eligible.size(), static_cast<size_t>(options_.max_seed_landmarks));
    if (n < 3) return false;
    std::vector<Eigen::Vector2d> p(n);
    for (size_t i = 0; i < n; ++i) p[i] = view.mean(nb.eligible[i]);

    // Delaunay triangles of the nearest eligible landmarks, closest to the vehicle first.
    std::vector<std::pair<double, std::array<size_t, 3>>> tris;
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1; j < n; ++j)
            for (size_t k = j + 1; k < n; ++k)
            {
                if (cross(p[j] - p[i], p[k] - p[i]) == 0) continue;
                if (view.isVirtual(nb.eligible[i]) + view.isVirtual(nb.eligible[j]) +
                        view.isVirtual(nb.eligible[k]) > 1)
                    continue;
                bool empty = true;
                for (size_t m = 0; m < n && empty; ++m)
                    if (m != i && m != j && m != k && inCircle(p[i], p[j], p[k], p[m]) > 0)
                        empty = false;
                if (!empty) continue;
                const double d = ((p[i] + p[j] + p[k]) / 3.0 - nb.vehicle).norm();
                tris.push_back({d, {i, j, k}});
            }
    std::sort(tris.begin(), tris.end());

    for (const auto& [d, t] : tris)
    {
        const std::array<long, 3> ids{nb.eligible[t[0]], nb.eligible[t[1]], nb.eligible[t[2]]};
        if (containsOtherLandmark({p[t[0]], p[t[1]], p[t[2]]}, ids, view, nb.nearby)) continue;
        long id = -1;
        if (tryAddRegion(ids, view, time, &id).accepted())
        {
            created.push_back(id);
            return true;
        }
    }
    return false;
}

}  // namespace hymm::ltr
