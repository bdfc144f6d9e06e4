/**
 * @file RegionPartition.cpp
 * @brief Region bookkeeping, point lookup grid and removal. Growth (candidate
 *        proposal) lives in RegionPartitionGrowth.cpp, the text format in
 *        RegionPartitionText.cpp, the run state in RegionPartitionState.cpp.
 */
#include "hymm/ltr/RegionPartition.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hymm::ltr
{
namespace
{
// Closed-triangle tolerance of the point lookup, in local (barycentric) units.
constexpr double kLookupTol = 1e-12;

/** Local coordinates of p in triangle v, or nullopt if v is degenerate. Uses the same
 *  arithmetic as TriangleFrame::toLocal so lookups agree with it. */
std::optional<Eigen::Vector2d> localIn(const TriangleFrame::Vertices& v, const Eigen::Vector2d& p)
{
    Eigen::Matrix2d d;
    d.col(0) = v[1] - v[0];
    d.col(1) = v[2] - v[0];
    if (!(std::abs(d.determinant()) > 0)) return std::nullopt;
    return Eigen::Vector2d(d.inverse() * (p - v[0]));
}
}  // namespace

// ---------------------------------------------------------------------------------
// Bookkeeping
// ---------------------------------------------------------------------------------
RegionPartition::RegionPartition(const Options& options)
    : options_(options), checker_(options.conditions)
{
    options_.validate();
}

std::int64_t RegionPartition::cellKey(long ix, long iy) const
{
    const auto ux = static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix));
    const auto uy = static_cast<std::uint64_t>(static_cast<std::uint32_t>(iy));
    return static_cast<std::int64_t>((ux << 32) | uy);
}

void RegionPartition::cellRange(
    const TriangleFrame::Vertices& v, long& x0, long& y0, long& x1, long& y1) const
{
    const double c = options_.grid_cell_size_m;
    // A NaN has no cell (and its cast to an index is undefined): a vertex or a box corner
    // that is not finite is an error of the caller, never a silent wrong cell.
    for (const auto& p : v)
        if (!p.allFinite()) throw std::invalid_argument("RegionPartition: a position that is not finite has no grid cell");
    double lx = v[0].x(), hx = lx, ly = v[0].y(), hy = ly;
    for (const auto& p : v)
    {
        lx = std::min(lx, p.x());
        hx = std::max(hx, p.x());
        ly = std::min(ly, p.y());
        hy = std::max(hy, p.y());
    }
    // Cell keys keep 32 bits per axis; clamping first keeps absurd (but finite) positions,
    // e.g. from corrupt odometry, from overflowing the conversion.
    constexpr double kMaxCell = double(1L << 30);
    const auto cell = [&](double coord) {
        return static_cast<long>(std::clamp(std::floor(coord / c), -kMaxCell, kMaxCell));
    };
    x0 = cell(lx);
    x1 = cell(hx);
    y0 = cell(ly);
    y1 = cell(hy);
}

void RegionPartition::indexRegion(const Region& r)
{
    long x0, y0, x1, y1;
    cellRange(r.current, x0, y0, x1, y1);
    for (long ix = x0; ix <= x1; ++ix)
        for (long iy = y0; iy <= y1; ++iy) grid_[cellKey(ix, iy)].push_back(r.id);
}

void RegionPartition::unindexRegion(const Region& r)
{
    long x0, y0, x1, y1;
    cellRange(r.current, x0, y0, x1, y1);
    for (long ix = x0; ix <= x1; ++ix)
        for (long iy = y0; iy <= y1; ++iy)
        {
            const auto it = grid_.find(cellKey(ix, iy));
            if (it == grid_.end()) continue;
            auto& ids = it->second;
            ids.erase(std::remove(ids.begin(), ids.end(), r.id), ids.end());
            if (ids.empty()) grid_.erase(it);
        }
}

long RegionPartition::insertRegion(Region r)
{
    // Keep every triangle counter-clockwise so that alpha, beta have one orientation.
    Eigen::Matrix2d d;
    d.col(0) = r.reference[1] - r.reference[0];
    d.col(1) = r.reference[2] - r.reference[0];
    if (d.determinant() < 0)
    {
        std::swap(r.vertex_ids[1], r.vertex_ids[2]);
        std::swap(r.reference[1], r.reference[2]);
        std::swap(r.current[1], r.current[2]);
    }
    if (r.id < 0) r.id = next_id_;
    next_id_ = std::max(next_id_, r.id + 1);
    for (int k = 0; k < 3; ++k)
    {
        const long a = r.vertex_ids[static_cast<size_t>(k)];
        edges_[edgeKey(a, r.vertex_ids[static_cast<size_t>((k + 1) % 3)])].push_back(r.id);
        by_landmark_[a].push_back(r.id);
    }
    indexRegion(r);
    const long id = r.id;
    regions_.emplace(id, std::move(r));
    return id;
}

CheckResult RegionPartition::tryAddRegion(
    const std::array<long, 3>& ids, const LandmarkCovarianceView& view, double time, long* id)
{
    for (const long l : ids)
        if (!view.has(l)) return checker_.check(ids, view, {});  // reports UnknownLandmark
    if (view.isVirtual(ids[0]) + view.isVirtual(ids[1]) + view.isVirtual(ids[2]) > 1)
    {
        CheckResult r;
        r.reason = BaseCondition::TwoVirtualVertices;
        r.detail = "virtual-virtual correlations are not kept: at most one virtual vertex";
        return r;
    }
    const TriangleFrame::Vertices v{view.mean(ids[0]), view.mean(ids[1]), view.mean(ids[2])};
    // Overlap only against regions whose boxes meet the candidate's (grid query).
    const CheckResult res = checker_.check(ids, view, nearbyTriangles(v));
    if (!res.accepted()) return res;
    Region r;
    r.vertex_ids = ids;
    r.reference = v;
    r.current = v;
    r.creation_time = time;
    const long new_id = insertRegion(std::move(r));
    if (id) *id = new_id;
    return res;
}

std::vector<TriangleFrame::Vertices> RegionPartition::nearbyTriangles(
    const TriangleFrame::Vertices& v) const
{
    Eigen::Vector2d lo = v[0], hi = v[0];
    for (const auto& p : v)
    {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    std::vector<TriangleFrame::Vertices> out;
    for (const long id : regionsInBox(lo, hi)) out.push_back(regions_.at(id).current);
    return out;
}

void RegionPartition::refreshRegion(Region& r, const LandmarkCovarianceView& view)
{
    long x0, y0, x1, y1;
    cellRange(r.current, x0, y0, x1, y1);
    const TriangleFrame::Vertices before = r.current;
    for (size_t k = 0; k < 3; ++k)
        if (view.has(r.vertex_ids[k])) r.current[k] = view.mean(r.vertex_ids[k]);
    long nx0, ny0, nx1, ny1;
    cellRange(r.current, nx0, ny0, nx1, ny1);
    if (nx0 == x0 && ny0 == y0 && nx1 == x1 && ny1 == y1) return;  // same cells
    Region old = r;
    old.current = before;
    unindexRegion(old);
    indexRegion(r);
}

void RegionPartition::updateVertexPositions(const LandmarkCovarianceView& view)
{
    for (auto& kv : regions_) refreshRegion(kv.second, view);
}

void RegionPartition::refreshNear(
    const LandmarkCovarianceView& view, const Eigen::Vector2d& centre, double radius)
{
    const Eigen::Vector2d half = Eigen::Vector2d::Constant(radius);
    for (const long id : regionsInBox(centre - half, centre + half))
        refreshRegion(regions_.at(id), view);
}

std::vector<long> RegionPartition::updateNear(
    const LandmarkCovarianceView& view, double time, double refresh_radius_m)
{
    const Eigen::Vector2d vehicle = view.vehiclePose().head<2>();
    refreshNear(view, vehicle,
                std::max(options_.search_radius_m, refresh_radius_m) + options_.grid_cell_size_m);
    return grow(view, time);
}

std::vector<long> RegionPartition::regionsWithMissingLandmarks(
    const LandmarkCovarianceView& view) const
{
    std::vector<long> out;
    for (const auto& [id, r] : regions_)
        if (!view.has(r.vertex_ids[0]) || !view.has(r.vertex_ids[1]) || !view.has(r.vertex_ids[2]))
            out.push_back(id);
    return out;
}

std::vector<long> RegionPartition::regionsWithMissingLandmarksNear(
    const LandmarkCovarianceView& view, const Eigen::Vector2d& centre, double radius) const
{
    const Eigen::Vector2d half = Eigen::Vector2d::Constant(radius);
    std::vector<long> out;
    for (const long id : regionsInBox(centre - half, centre + half))
    {
        const Region& r = regions_.at(id);
        if (!view.has(r.vertex_ids[0]) || !view.has(r.vertex_ids[1]) || !view.has(r.vertex_ids[2]))
            out.push_back(id);
    }
    return out;
}

// ---------------------------------------------------------------------------------
// Lookup and access
// ---------------------------------------------------------------------------------
std::vector<long> RegionPartition::findRegions(const Eigen::Vector2d& p) const
{
    std::vector<long> out;
    if (!p.allFinite()) return out;  // nowhere: in no region
    long ix, iy, unused_x, unused_y;
    cellRange({p, p, p}, ix, iy, unused_x, unused_y);
    const auto it = grid_.find(cellKey(ix, iy));
    if (it == grid_.end()) return out;
    for (const long id : it->second)
    {
        const auto l = localIn(regions_.at(id).current, p);
        if (l && TriangleFrame::insideLocal(*l, kLookupTol)) out.push_back(id);
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::optional<long> RegionPartition::findRegion(const Eigen::Vector2d& p) const
{
    const std::vector<long> ids = findRegions(p);
    if (ids.empty()) return std::nullopt;
    return ids.front();
}

std::vector<long> RegionPartition::regionsInBox(
    const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) const
{
    std::vector<long> out;
    if (!lo.allFinite() || !hi.allFinite()) return out;
    long x0, y0, x1, y1;
    cellRange({lo, hi, hi}, x0, y0, x1, y1);
    // A box of more cells than the grid holds walks the grid instead: the cost is bounded
    // by the map, whatever the box.
    const double box_cells = double(x1 - x0 + 1) * double(y1 - y0 + 1);
    if (box_cells > double(grid_.size()))
    {
        for (const auto& [key, ids] : grid_)
        {
            const long ix = static_cast<std::int32_t>(static_cast<std::uint64_t>(key) >> 32);
            const long iy = static_cast<std::int32_t>(static_cast<std::uint64_t>(key) & 0xffffffffu);
            if (ix >= x0 && ix <= x1 && iy >= y0 && iy <= y1) out.insert(out.end(), ids.begin(), ids.end());
        }
    }
    else
        for (long ix = x0; ix <= x1; ++ix)
            for (long iy = y0; iy <= y1; ++iy)
            {
                const auto it = grid_.find(cellKey(ix, iy));
                if (it != grid_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
            }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

const Region& RegionPartition::region(long id) const
{
    const auto it = regions_.find(id);
    if (it == regions_.end())
        throw std::out_of_range("RegionPartition: unknown region id " + std::to_string(id));
    return it->second;
}

std::vector<long> RegionPartition::regionIds() const
{
    std::vector<long> out;
    out.reserve(regions_.size());
    for (const auto& kv : regions_) out.push_back(kv.first);
    return out;
}

std::vector<long> RegionPartition::regionsUsingLandmark(long landmark_id) const
{
    const auto it = by_landmark_.find(landmark_id);
    if (it == by_landmark_.end()) return {};
    std::vector<long> out = it->second;
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<long> RegionPartition::edgeNeighbours(long id) const
{
    const Region& r = region(id);
    std::vector<long> out;
    for (size_t k = 0; k < 3; ++k)
        for (const long other : edges_.at(edgeKey(r.vertex_ids[k], r.vertex_ids[(k + 1) % 3])))
            if (other != id) out.push_back(other);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

TriangleFrame RegionPartition::referenceFrame(long id) const
{
    return TriangleFrame(region(id).reference);
}

TriangleFrame RegionPartition::currentFrame(long id) const
{
    return TriangleFrame(region(id).current);
}

AffineRegionMap RegionPartition::referenceToCurrent(long id) const
{
    return AffineRegionMap(referenceFrame(id), currentFrame(id));
}

// ---------------------------------------------------------------------------------
// Removal
// ---------------------------------------------------------------------------------
bool RegionPartition::removeRegion(long id)
{
    const auto it = regions_.find(id);
    if (it == regions_.end()) return false;
    const Region& r = it->second;
    unindexRegion(r);
    auto drop = [id](std::vector<long>& v) { v.erase(std::remove(v.begin(), v.end(), id), v.end()); };
    for (size_t k = 0; k < 3; ++k)
    {
        const EdgeKey e = edgeKey(r.vertex_ids[k], r.vertex_ids[(k + 1) % 3]);
        drop(edges_[e]);
        if (edges_[e].empty()) edges_.erase(e);
        auto& lm = by_landmark_[r.vertex_ids[k]];
        drop(lm);
        if (lm.empty()) by_landmark_.erase(r.vertex_ids[k]);
    }
    regions_.erase(it);
    return true;
}

std::vector<long> RegionPartition::removeRegionsUsingLandmark(long landmark_id)
{
    const std::vector<long> ids = regionsUsingLandmark(landmark_id);
    for (const long id : ids) removeRegion(id);
    return ids;
}

void RegionPartition::clear()
{
    regions_.clear();
    edges_.clear();
    by_landmark_.clear();
    grid_.clear();
    next_id_ = 0;
}

}  // namespace hymm::ltr
