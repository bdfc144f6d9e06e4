#include "hymm/dense/OccupancyLayer.h"

#include "hymm/dense/geometry.h"

#include <hymm/core/config_utils.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace hymm::dense
{
namespace
{
// Tolerance [m] for "cell centre inside the current triangle" when rendering: keeps
// centres that fall exactly on a shared edge from being dropped by rounding.
constexpr double kRenderEdgeTol = 1e-9;

Eigen::Vector2d boxLo(const hymm::ltr::TriangleFrame::Vertices& v)
{
    return v[0].cwiseMin(v[1]).cwiseMin(v[2]);
}
Eigen::Vector2d boxHi(const hymm::ltr::TriangleFrame::Vertices& v)
{
    return v[0].cwiseMax(v[1]).cwiseMax(v[2]);
}
}  // namespace

hymm::core::OptionTable OccupancyLayer::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("cell_size_m", cell_size_m, "m", between(0.001, 100), "local grid cell");
    t.real("prob_hit", prob_hit, "", openInterval(0, 1), "inverse sensor model at the cell of a return (> prob_prior)");
    t.real("prob_miss", prob_miss, "", openInterval(0, 1), "inverse sensor model along the beam before it (< prob_prior)");
    t.real("prob_prior", prob_prior, "", openInterval(0, 1), "P(C_i) before any observation");
    t.real("prob_clamp_min", prob_clamp_min, "", openInterval(0, 1), "lower clamp of the posterior (<= prob_prior)");
    t.real("prob_clamp_max", prob_clamp_max, "", openInterval(0, 1), "upper clamp of the posterior (>= prob_prior)");
    t.real("coarse_cell_size_m", coarse_cell_size_m, "m", between(0, 1000),
           "cell after coarsen(); 0 = never coarsen, else > cell_size_m");
    t.real("coarsen_cells_percent", coarsen_cells_percent, "", above(0, 1), "fraction of free cells needed to coarsen");
    t.real("coarsen_min_prob", coarsen_min_prob, "", openInterval(0, 1), "a cell is free below this P");
    return t;
}

void OccupancyLayer::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void OccupancyLayer::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void OccupancyLayer::Options::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    if (!(cell_size_m > 0)) throwConfigError(s, "cell_size_m", std::to_string(cell_size_m), "must be > 0");
    const auto open01 = [&](const char* key, double v) {
        if (!(v > 0 && v < 1)) throwConfigError(s, key, std::to_string(v), "must be in (0, 1)");
    };
    open01("prob_hit", prob_hit);
    open01("prob_miss", prob_miss);
    open01("prob_prior", prob_prior);
    open01("prob_clamp_min", prob_clamp_min);
    open01("prob_clamp_max", prob_clamp_max);
    // A return must raise occupancy and a traversal lower it, else the grid cannot learn.
    if (!(prob_hit > prob_prior))
        throwConfigError(s, "prob_hit", std::to_string(prob_hit), "must be > prob_prior");
    if (!(prob_miss < prob_prior))
        throwConfigError(s, "prob_miss", std::to_string(prob_miss), "must be < prob_prior");
    if (!(prob_clamp_min <= prob_prior && prob_prior <= prob_clamp_max))
        throwConfigError(
            s, "prob_clamp_min", std::to_string(prob_clamp_min),
            "need prob_clamp_min <= prob_prior <= prob_clamp_max");
    if (!(coarse_cell_size_m == 0 || (std::isfinite(coarse_cell_size_m) && coarse_cell_size_m > cell_size_m)))
        throwConfigError(
            s, "coarse_cell_size_m", std::to_string(coarse_cell_size_m), "must be 0 (off) or > cell_size_m");
    if (!(coarsen_cells_percent > 0 && coarsen_cells_percent <= 1))
        throwConfigError(s, "coarsen_cells_percent", std::to_string(coarsen_cells_percent), "must be in (0, 1]");
    open01("coarsen_min_prob", coarsen_min_prob);
}

float OccupancyLayer::Options::hitIncrement() const
{
    return static_cast<float>(logit(prob_hit) - logit(prob_prior));
}
float OccupancyLayer::Options::missIncrement() const
{
    return static_cast<float>(logit(prob_miss) - logit(prob_prior));
}
float OccupancyLayer::Options::priorLogOdds() const { return static_cast<float>(logit(prob_prior)); }
float OccupancyLayer::Options::clampMinLogOdds() const
{
    return static_cast<float>(logit(prob_clamp_min));
}
float OccupancyLayer::Options::clampMaxLogOdds() const
{
    return static_cast<float>(logit(prob_clamp_max));
}

OccupancyLayer::OccupancyLayer(
    const Options& options, const hymm::ltr::TriangleFrame::Vertices& reference)
    : options_(options),
      reference_(reference),
      grid_(LogOddsGrid::covering(
          boxLo(reference), boxHi(reference), options.cell_size_m, options.priorLogOdds()))
{
    options_.validate();
    restrictToTriangle();
}

void OccupancyLayer::restrictToTriangle()
{
    for (int iy = 0; iy < grid_.sizeY(); ++iy)
        for (int ix = 0; ix < grid_.sizeX(); ++ix)
        {
            const Eigen::Vector2d lo = grid_.cellMin(ix, iy);
            const Eigen::Vector2d hi = lo + Eigen::Vector2d::Constant(grid_.cellSize());
            grid_.setUpdatable(ix, iy, boxIntersectsTriangle(lo, hi, reference_));
        }
}

void OccupancyLayer::insert(const RegionScan& scan)
{
    for (const FreeRay& ray : scan.rays)
    {
        grid_.markFree(ray.from, ray.to, ray.ends_at_hit);
        if (ray.ends_at_hit) grid_.markOccupied(ray.to);
    }
    grid_.applyMarks(
        options_.missIncrement(), options_.hitIncrement(), options_.clampMinLogOdds(),
        options_.clampMaxLogOdds());
}

double OccupancyLayer::freeFraction(double min_prob) const
{
    const double l_min = logit(min_prob);
    size_t cells = 0, free = 0;
    for (int iy = 0; iy < grid_.sizeY(); ++iy)
        for (int ix = 0; ix < grid_.sizeX(); ++ix)
        {
            if (!grid_.updatable(ix, iy)) continue;
            ++cells;
            if (grid_.logOdds(ix, iy) < l_min) ++free;
        }
    return cells == 0 ? 0.0 : static_cast<double>(free) / static_cast<double>(cells);
}

bool OccupancyLayer::isCoarse() const
{
    return options_.coarse_cell_size_m > 0 && grid_.cellSize() >= options_.coarse_cell_size_m;
}

bool OccupancyLayer::coarsen()
{
    if (options_.coarse_cell_size_m <= 0 || isCoarse()) return false;
    if (!(freeFraction(options_.coarsen_min_prob) > options_.coarsen_cells_percent)) return false;  // Sec. 4.1.3
    LogOddsGrid coarse = LogOddsGrid::covering(
        boxLo(reference_), boxHi(reference_), options_.coarse_cell_size_m, grid_.initialLogOdds());
    const size_t n = static_cast<size_t>(coarse.sizeX()) * static_cast<size_t>(coarse.sizeY());
    std::vector<float> max_l(n, -std::numeric_limits<float>::infinity());
    std::vector<double> sum_l(n, 0.0);
    std::vector<size_t> count(n, 0);
    for (int iy = 0; iy < grid_.sizeY(); ++iy)
        for (int ix = 0; ix < grid_.sizeX(); ++ix)
        {
            int cx, cy;
            if (!grid_.updatable(ix, iy) || !coarse.cellOf(grid_.cellCentre(ix, iy), cx, cy)) continue;
            const size_t k = static_cast<size_t>(cy) * static_cast<size_t>(coarse.sizeX()) + static_cast<size_t>(cx);
            const float l = grid_.logOdds(ix, iy);
            max_l[k] = std::max(max_l[k], l);
            sum_l[k] += l;
            ++count[k];
        }
    for (int cy = 0; cy < coarse.sizeY(); ++cy)
        for (int cx = 0; cx < coarse.sizeX(); ++cx)
        {
            const size_t k = static_cast<size_t>(cy) * static_cast<size_t>(coarse.sizeX()) + static_cast<size_t>(cx);
            if (count[k] == 0) continue;  // border cell beyond the fine grid: stays at the prior
            // Occupied wins, so obstacles survive; otherwise the mean keeps free/unknown.
            coarse.setLogOdds(cx, cy, max_l[k] > 0 ? max_l[k] : static_cast<float>(sum_l[k] / static_cast<double>(count[k])));
        }
    grid_ = std::move(coarse);
    restrictToTriangle();
    return true;
}

size_t OccupancyLayer::memoryBytes() const { return sizeof(*this) - sizeof(grid_) + grid_.memoryBytes(); }

double OccupancyLayer::probabilityAt(const Eigen::Vector2d& p_ref) const
{
    int ix, iy;
    if (!grid_.cellOf(p_ref, ix, iy)) return logistic(grid_.initialLogOdds());
    return logistic(grid_.logOdds(ix, iy));
}

void OccupancyLayer::renderInto(
    const hymm::ltr::AffineRegionMap& reference_to_current, mrpt::maps::CMetricMap& out) const
{
    auto* og = dynamic_cast<mrpt::maps::COccupancyGridMap2D*>(&out);
    if (!og)
        throw std::invalid_argument(
            std::string("OccupancyLayer::renderInto: cannot draw a grid into a ") +
            out.GetRuntimeClass()->className);
    hymm::ltr::TriangleFrame::Vertices cur;
    for (size_t k = 0; k < 3; ++k) cur[k] = reference_to_current.mapPoint(reference_[k]);
    const Eigen::Vector2d lo = boxLo(cur), hi = boxHi(cur);
    const int x0 = std::max(0, og->x2idx(lo.x())), y0 = std::max(0, og->y2idx(lo.y()));
    const int x1 = std::min(static_cast<int>(og->getSizeX()) - 1, og->x2idx(hi.x()));
    const int y1 = std::min(static_cast<int>(og->getSizeY()) - 1, og->y2idx(hi.y()));
    for (int cy = y0; cy <= y1; ++cy)
        for (int cx = x0; cx <= x1; ++cx)
        {
            const Eigen::Vector2d c(og->idx2x(static_cast<size_t>(cx)), og->idx2y(static_cast<size_t>(cy)));
            if (!triangleContains(cur, c, kRenderEdgeTol)) continue;
            int ix, iy;
            if (!grid_.cellOf(reference_to_current.inverseMapPoint(c), ix, iy)) continue;
            if (render_mode_ != RenderMode::Overwrite && grid_.logOdds(ix, iy) == grid_.initialLogOdds()) continue;
            const float p = static_cast<float>(logistic(grid_.logOdds(ix, iy)));
            if (render_mode_ == RenderMode::MaxObserved)
            {
                const float was = og->getCell(cx, cy);
                // 0.5 is the output's "nothing drawn" value (within its quantisation).
                if (std::abs(was - 0.5f) > 1e-3f && p <= was) continue;
            }
            og->setCell(cx, cy, p);
        }
}

void OccupancyLayer::save(std::ostream& out) const { grid_.save(out); }

void OccupancyLayer::load(std::istream& in) { grid_ = LogOddsGrid::load(in); }

}  // namespace hymm::dense
