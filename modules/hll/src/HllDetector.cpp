/**
 * @file HllDetector.cpp
 * @brief High-level landmark search (thesis 6.1.3): corners on the local occupancy
 *        patch, pairs, rectangles, acceptance by the SOG layer.
 */
#include "hymm/hll/HllDetector.h"

#include <hymm/dense/LocalDenseMap.h>
#include <hymm/dense/OccupancyLayer.h>
#include <hymm/dense/SogLayer.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace hymm::hll
{
// ---------------------------------------------------------------------------------
// Rectangles
// ---------------------------------------------------------------------------------
Vec2 OrientedRect::toLocal(const Vec2& p) const
{
    const double c = std::cos(phi), s = std::sin(phi);
    const Vec2 d = p - centre;
    return {c * d.x() + s * d.y(), -s * d.x() + c * d.y()};
}

bool OrientedRect::contains(const Vec2& p) const
{
    const Vec2 q = toLocal(p);
    return std::abs(q.x()) <= half.x() && std::abs(q.y()) <= half.y();
}

std::array<Vec2, 4> OrientedRect::corners() const
{
    const double c = std::cos(phi), s = std::sin(phi);
    const Vec2 ex(c * half.x(), s * half.x()), ey(-s * half.y(), c * half.y());
    return {centre - ex - ey, centre + ex - ey, centre + ex + ey, centre - ex + ey};
}

OrientedRect OrientedRect::placed(const Vec3& z) const
{
    OrientedRect r = *this;
    const double c = std::cos(z.z()), s = std::sin(z.z());
    r.centre = Vec2(c * centre.x() - s * centre.y() + z.x(), s * centre.x() + c * centre.y() + z.y());
    r.phi = phi + z.z();
    return r;
}

bool overlaps(const OrientedRect& a, const OrientedRect& b)
{
    // Separating-axis theorem: two convex polygons are disjoint iff their projections
    // are disjoint on one of the edge normals (two per rectangle).
    const auto ca = a.corners(), cb = b.corners();
    for (const double phi : {a.phi, a.phi + M_PI / 2, b.phi, b.phi + M_PI / 2})
    {
        const Vec2 axis(std::cos(phi), std::sin(phi));
        double amin = std::numeric_limits<double>::infinity(), amax = -amin, bmin = amin, bmax = -amin;
        for (const Vec2& p : ca) amin = std::min(amin, p.dot(axis)), amax = std::max(amax, p.dot(axis));
        for (const Vec2& p : cb) bmin = std::min(bmin, p.dot(axis)), bmax = std::max(bmax, p.dot(axis));
        if (amax < bmin || bmax < amin) return false;
    }
    return true;
}

OrientedRect boundingRect(const std::vector<Vec2>& points, double grow_m)
{
    if (points.empty()) throw std::invalid_argument("boundingRect: no points");
    Vec2 lo = points.front(), hi = points.front();
    for (const Vec2& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    OrientedRect r;
    r.centre = 0.5 * (lo + hi);
    r.half = 0.5 * (hi - lo) + Vec2::Constant(grow_m);
    return r;
}

size_t countInside(const OrientedRect& rect, const std::vector<HllDetector::Gaussian>& gaussians)
{
    size_t n = 0;
    for (const auto& g : gaussians) n += rect.contains(g.mean) ? 1 : 0;
    return n;
}

double outlineInside(const OrientedRect& rect, const std::vector<HllDetector::Gaussian>& gaussians,
                     double cell_m)
{
    if (!(cell_m > 0)) throw std::invalid_argument("outlineInside: cell_m must be > 0");
    // Distinct cells of the rectangle's own frame holding a mean: however often the SOG
    // layer saw a wall (it adds Gaussians on every revisit, Sec. 4.3.2), a metre of it
    // fills about 1 / cell_m cells. The frame runs along the pair of corners, so the walls
    // of a box are aligned with it; a wall at an angle a counts |cos a| + |sin a| times
    // its length (at most sqrt(2)).
    std::vector<std::pair<long, long>> cells;
    for (const auto& g : gaussians)
    {
        const Vec2 q = rect.toLocal(g.mean);
        if (std::abs(q.x()) > rect.half.x() || std::abs(q.y()) > rect.half.y()) continue;
        cells.emplace_back(static_cast<long>(std::floor(q.x() / cell_m)), static_cast<long>(std::floor(q.y() / cell_m)));
    }
    std::sort(cells.begin(), cells.end());
    return static_cast<double>(std::unique(cells.begin(), cells.end()) - cells.begin()) * cell_m;
}

// ---------------------------------------------------------------------------------
// Options
// ---------------------------------------------------------------------------------
core::OptionTable HllDetector::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("period_s", period_s, "s", above(0), "log time between two searches (thesis: 60 s)");
    t.real("search_half_size_m", search_half_size_m, "m", above(0),
           "half-side of the square around the vehicle whose regions are searched");
    t.real("cell_size_m", cell_size_m, "m", above(0, 10), "cell of the rendered occupancy patch");
    t.real("occupied_prob", occupied_prob, "", openInterval(0, 1),
           "P(occupied) above which a cell is drawn occupied in the corner image");
    t.real("blur_sigma_cells", blur_sigma_cells, "cells", atLeast(0),
           "Gaussian smoothing of the corner image before Harris (0: none)");
    t.integer("harris_block_size", harris_block_size, "cells", 2, 31,
              "neighbourhood of the Harris matrix");
    t.real("harris_k", harris_k, "", openInterval(0, 0.25), "Harris' free parameter k");
    t.real("quality_level", quality_level, "", openInterval(0, 1),
           "corners weaker than this times the strongest of the patch are dropped");
    t.real("min_corner_distance_m", min_corner_distance_m, "m", atLeast(0),
           "non-maximum suppression radius between corners");
    t.integer("max_corners", max_corners, "", 1, 100000, "strongest corners kept per search");
    t.real("min_object_extent_m", min_object_extent_m, "m", atLeast(0),
           "occupied components with a shorter bounding-box diagonal (poles) make no corners (0: all do)");
    t.real("landmark_clearance_m", landmark_clearance_m, "m", atLeast(0),
           "corners closer than this to a point landmark's estimate are dropped (no duplicate)");
    t.real("pair_max_distance_m", pair_max_distance_m, "m", above(0),
           "a corner pairs with its nearest neighbour this close (thesis: 12 m)");
    t.real("min_pair_distance_m", min_pair_distance_m, "m", atLeast(0),
           "corners closer than this are not paired");
    t.real("margin_m", margin_m, "m", atLeast(0), "rectangle beyond the pair of corners (thesis: 5 m)");
    t.integer("min_gaussians", min_gaussians, "", 1, 100000000,
              "SOG Gaussians needed inside a rectangle to accept it (thesis: 200)");
    t.real("min_outline_m", min_outline_m, "m", atLeast(0),
           "outline length needed inside a rectangle (cells of outline_cell_m holding a Gaussian; 0: no test)");
    t.real("outline_cell_m", outline_cell_m, "m", above(0, 10), "cell that measures the outline length");
    return t;
}

const char* HllDetector::outcomeName(Outcome o)
{
    switch (o)
    {
        case Outcome::accepted: return "accepted";
        case Outcome::too_few_gaussians: return "too_few_gaussians";
        case Outcome::outline_too_short: return "outline_too_short";
        case Outcome::overlaps_landmark: return "overlaps_landmark";
        case Outcome::overlaps_candidate: return "overlaps_candidate";
    }
    return "?";
}

size_t HllDetector::Search::accepted() const
{
    return static_cast<size_t>(std::count_if(candidates.begin(), candidates.end(), [](const Candidate& c)
                                             { return c.outcome == Outcome::accepted; }));
}

HllDetector::HllDetector(const Options& options) : options_(options)
{
    if (!(options_.cell_size_m > 0) || !(options_.search_half_size_m > 0) || !(options_.period_s > 0))
        throw std::invalid_argument("HllDetector: cell_size_m, search_half_size_m and period_s must be > 0");
}

// ---------------------------------------------------------------------------------
// Steps
// ---------------------------------------------------------------------------------
namespace
{
/** The corner image: cells with P(occupied) > `occupied_prob`, without the occupied
 *  connected components (8-neighbours) whose bounding box has a diagonal shorter than
 *  `min_extent_cells`. A pole is such a component (a blob of a few cells at the tip of
 *  its laser shadow); its Harris response is as strong as a building's corner, but it is
 *  a point landmark, not an object with two corners (thesis 6.1.3 looks for objects). */
cv::Mat objectImage(const mrpt::maps::COccupancyGridMap2D& grid, double occupied_prob, double min_extent_cells,
                    size_t* dropped)
{
    const int w = static_cast<int>(grid.getSizeX()), h = static_cast<int>(grid.getSizeY());
    // The unknown/free border of the explored area (scan limits) is not an object and
    // must not make corners: only occupied cells are drawn.
    cv::Mat img(h, w, CV_8UC1, cv::Scalar(0));
    for (int cy = 0; cy < h; ++cy)
        for (int cx = 0; cx < w; ++cx)
            if (grid.getCell(cx, cy) > occupied_prob) img.at<unsigned char>(cy, cx) = 255;
    if (!(min_extent_cells > 0)) return img;
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(img, labels, stats, centroids, 8, CV_32S);
    std::vector<unsigned char> keep(static_cast<size_t>(n), 1);
    for (int l = 1; l < n; ++l)  // label 0: background
    {
        const double bw = stats.at<int>(l, cv::CC_STAT_WIDTH), bh = stats.at<int>(l, cv::CC_STAT_HEIGHT);
        if (std::hypot(bw, bh) < min_extent_cells)
        {
            keep[static_cast<size_t>(l)] = 0;
            if (dropped) ++*dropped;
        }
    }
    for (int cy = 0; cy < h; ++cy)
        for (int cx = 0; cx < w; ++cx)
            if (!keep[static_cast<size_t>(labels.at<int>(cy, cx))]) img.at<unsigned char>(cy, cx) = 0;
    return img;
}
}  // namespace

std::vector<Vec2> HllDetector::detectCorners(const mrpt::maps::COccupancyGridMap2D& grid,
                                             const std::vector<Vec2>& point_landmarks, CornerStats* stats) const
{
    const int w = static_cast<int>(grid.getSizeX()), h = static_cast<int>(grid.getSizeY());
    std::vector<Vec2> out;
    if (w < options_.harris_block_size + 2 || h < options_.harris_block_size + 2) return out;
    const cv::Mat img = objectImage(grid, options_.occupied_prob, options_.min_object_extent_m / grid.getResolution(),
                                    stats ? &stats->components_dropped : nullptr);
    if (cv::countNonZero(img) == 0) return out;
    // Only the point landmarks that can lie within the clearance of a corner of this patch:
    // the map's landmarks are read once, and the per-corner test below then costs the
    // landmarks near the vehicle, not the whole map.
    const double r = options_.landmark_clearance_m;
    std::vector<Vec2> near;
    for (const Vec2& l : point_landmarks)
        if (l.x() > grid.getXMin() - r && l.x() < grid.getXMax() + r && l.y() > grid.getYMin() - r &&
            l.y() < grid.getYMax() + r)
            near.push_back(l);
    // Smoothing first: a wall that is not aligned with the grid is a staircase of cells
    // whose steps are corners at the scale of a cell, not of the object.
    cv::Mat smooth = img;
    if (options_.blur_sigma_cells > 0)
        cv::GaussianBlur(img, smooth, cv::Size(), options_.blur_sigma_cells, options_.blur_sigma_cells);
    // A corner is where walls meet: it must lie on (or next to) an occupied cell, not in
    // the middle of a small blob the smoothing filled.
    cv::Mat near_occupied;
    cv::dilate(img, near_occupied, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
    std::vector<cv::Point2f> pts;
    const double min_d = options_.min_corner_distance_m / grid.getResolution();
    cv::goodFeaturesToTrack(smooth, pts, options_.max_corners, options_.quality_level, min_d, near_occupied,
                            options_.harris_block_size, /*useHarrisDetector=*/true, options_.harris_k);
    out.reserve(pts.size());
    for (const auto& p : pts)
    {
        // Sub-cell positions: cell centre of index i is idx2x(i); linear in between.
        const Vec2 c(grid.getXMin() + (p.x + 0.5) * grid.getResolution(),
                     grid.getYMin() + (p.y + 0.5) * grid.getResolution());
        // A corner on a point landmark would make an HLL that duplicates it (6.1: a new
        // landmark must be new); a pole next to a wall joins the wall's component.
        const bool on_landmark =
            std::any_of(near.begin(), near.end(), [&](const Vec2& l) { return (l - c).norm() < r; });
        if (on_landmark)
        {
            if (stats) ++stats->near_landmark;
            continue;
        }
        out.push_back(c);
    }
    return out;
}

std::vector<std::pair<size_t, size_t>> HllDetector::pairCorners(const std::vector<Vec2>& c) const
{
    std::vector<std::pair<size_t, size_t>> pairs;
    for (size_t i = 0; i < c.size(); ++i)
    {
        size_t best = c.size();
        double best_d = std::numeric_limits<double>::infinity();
        for (size_t j = 0; j < c.size(); ++j)
        {
            if (j == i) continue;
            const double d = (c[j] - c[i]).norm();
            if (d >= options_.min_pair_distance_m && d < best_d) best_d = d, best = j;
        }
        if (best == c.size() || best_d > options_.pair_max_distance_m) continue;
        const auto p = std::minmax(i, best);
        if (std::find(pairs.begin(), pairs.end(), std::pair<size_t, size_t>(p.first, p.second)) == pairs.end())
            pairs.emplace_back(p.first, p.second);
    }
    return pairs;
}

OrientedRect HllDetector::pairRectangle(const Vec2& a, const Vec2& b) const
{
    OrientedRect r;
    r.centre = 0.5 * (a + b);
    const Vec2 d = b - a;
    r.phi = std::atan2(d.y(), d.x());
    r.half = Vec2(0.5 * d.norm() + options_.margin_m, options_.margin_m);
    return r;
}

std::vector<HllDetector::Candidate> HllDetector::evaluate(const std::vector<Vec2>& corners,
                                                          const std::vector<Gaussian>& gaussians,
                                                          const std::vector<OrientedRect>& exclusions) const
{
    std::vector<Candidate> cands;
    for (const auto& [i, j] : pairCorners(corners))
    {
        Candidate c;
        c.a = corners[i];
        c.b = corners[j];
        c.rect = pairRectangle(c.a, c.b);
        c.gaussians = countInside(c.rect, gaussians);
        c.outline_m = outlineInside(c.rect, gaussians, options_.outline_cell_m);
        cands.push_back(c);
    }
    // The richest candidates first (thesis: more Gaussians make the template easier to
    // observe); ties keep the pairing order.
    std::stable_sort(cands.begin(), cands.end(),
                     [](const Candidate& x, const Candidate& y) { return x.gaussians > y.gaussians; });
    std::vector<OrientedRect> taken;
    for (auto& c : cands)
    {
        if (c.gaussians < options_.min_gaussians)
            c.outcome = Outcome::too_few_gaussians;
        else if (c.outline_m < options_.min_outline_m)
            c.outcome = Outcome::outline_too_short;
        else if (std::any_of(exclusions.begin(), exclusions.end(),
                             [&](const OrientedRect& e) { return overlaps(c.rect, e); }))
            c.outcome = Outcome::overlaps_landmark;
        else if (std::any_of(taken.begin(), taken.end(),
                             [&](const OrientedRect& e) { return overlaps(c.rect, e); }))
            c.outcome = Outcome::overlaps_candidate;
        else
        {
            c.outcome = Outcome::accepted;
            taken.push_back(c.rect);
        }
    }
    return cands;
}

HllDetector::Search HllDetector::search(const Vec2& vehicle, const ltr::RegionPartition& partition,
                                        const dense::HybridMetricMap& map,
                                        const std::vector<OrientedRect>& exclusions, double t,
                                        const std::vector<Vec2>& point_landmarks) const
{
    Search s;
    s.t = t;
    const Vec2 half = Vec2::Constant(options_.search_half_size_m);
    s.lo = vehicle - half;
    s.hi = vehicle + half;
    const std::vector<long> ids = partition.regionsInBox(s.lo, s.hi);
    s.regions = ids.size();
    const float res = static_cast<float>(options_.cell_size_m);
    mrpt::maps::COccupancyGridMap2D grid(static_cast<float>(s.lo.x()), static_cast<float>(s.hi.x()),
                                         static_cast<float>(s.lo.y()), static_cast<float>(s.hi.y()), res);
    for (long id : ids)
    {
        const dense::LocalDenseMap* lm = map.localMap(id);
        if (!lm) continue;
        const auto* occ = lm->layerAs<dense::OccupancyLayer>(dense::OccupancyLayer::kKind);
        const auto* sog = lm->layerAs<dense::SogLayer>(dense::SogLayer::kKind);
        if (!occ && !sog) continue;
        std::optional<ltr::AffineRegionMap> a;
        try
        {
            a.emplace(partition.referenceToCurrent(id));
        }
        catch (const std::invalid_argument&)
        {
            ++s.regions_degenerate;  // current triangle no longer a frame
            continue;
        }
        if (occ) occ->renderInto(*a, grid);
        if (sog)
            for (size_t i = 0; i < sog->size(); ++i)
            {
                const auto g = sog->gaussianAt(i, *a);
                const Vec2 m(g.mean.x(), g.mean.y());
                // Gaussians of a region reaching outside the square are kept: a rectangle
                // near the border counts the whole object.
                s.gaussians.push_back({m, g.cov.asEigen()});
            }
    }
    CornerStats cs;
    s.corners = detectCorners(grid, point_landmarks, &cs);
    s.components_dropped = cs.components_dropped;
    s.corners_near_landmark = cs.near_landmark;
    s.candidates = evaluate(s.corners, s.gaussians, exclusions);
    return s;
}

}  // namespace hymm::hll
