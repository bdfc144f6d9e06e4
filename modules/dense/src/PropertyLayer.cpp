#include "hymm/dense/PropertyLayer.h"

#include "hymm/dense/geometry.h"
#include "text_io.h"

#include <hymm/core/config_utils.h>
#include <mrpt/maps/CHeightGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>
#include <stdexcept>

namespace hymm::dense
{
namespace
{
// Same tolerance as OccupancyLayer: a cell centre exactly on a shared edge is drawn.
constexpr double kRenderEdgeTol = 1e-9;

/** Global cells [x0, x1] x [y0, y1] of a grid with origin `o` and `res` that can hold
 *  centres inside the triangle `cur`, clipped to [0, nx) x [0, ny). */
struct CellRange
{
    int x0, y0, x1, y1;
};
CellRange rangeOver(
    const hymm::ltr::TriangleFrame::Vertices& cur, const Eigen::Vector2d& o, double res, int nx, int ny)
{
    const Eigen::Vector2d lo = cur[0].cwiseMin(cur[1]).cwiseMin(cur[2]);
    const Eigen::Vector2d hi = cur[0].cwiseMax(cur[1]).cwiseMax(cur[2]);
    return {std::max(0, static_cast<int>(std::floor((lo.x() - o.x()) / res))),
            std::max(0, static_cast<int>(std::floor((lo.y() - o.y()) / res))),
            std::min(nx - 1, static_cast<int>(std::floor((hi.x() - o.x()) / res))),
            std::min(ny - 1, static_cast<int>(std::floor((hi.y() - o.y()) / res)))};
}
}  // namespace

hymm::core::OptionTable PropertyLayer::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("cell_size_m", cell_size_m, "m", between(0.001, 100), "local cell (reference frame)");
    t.real("default_value_std", default_value_std, "value units", above(0, 1e9), "used when a return has no std");
    return t;
}

void PropertyLayer::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void PropertyLayer::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void PropertyLayer::Options::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    if (!(cell_size_m > 0) || !std::isfinite(cell_size_m))
        throwConfigError(s, "cell_size_m", std::to_string(cell_size_m), "must be finite and > 0");
    if (!(default_value_std > 0) || !std::isfinite(default_value_std))
        throwConfigError(s, "default_value_std", std::to_string(default_value_std), "must be finite and > 0");
}

PropertyLayer::PropertyLayer(const Options& options, const hymm::ltr::TriangleFrame::Vertices& reference)
    : options_(options), reference_(reference)
{
    options_.validate();
}

std::int64_t PropertyLayer::keyOf(const Eigen::Vector2d& p) const
{
    return pointCellKey(p, options_.cell_size_m);
}

void PropertyLayer::fuse(const Eigen::Vector2d& p_ref, double value, double value_std)
{
    if (!p_ref.allFinite()) throw std::invalid_argument("PropertyLayer: position is not finite");
    if (!std::isfinite(value))
        throw std::invalid_argument("PropertyLayer: value " + std::to_string(value) + " is not finite");
    if (!(value_std > 0) || !std::isfinite(value_std))
        throw std::invalid_argument(
            "PropertyLayer: value std " + std::to_string(value_std) + " must be finite and > 0");
    Cell& c = cells_[keyOf(p_ref)];
    const double info = 1.0 / (value_std * value_std);
    c.info += info;
    c.weighted += info * value;
    ++c.count;
}

void PropertyLayer::insert(const RegionScan& scan)
{
    if (scan.hit_values.empty()) return;
    if (scan.hit_values.size() != scan.hits.size())
        throw std::invalid_argument(
            "PropertyLayer::insert: " + std::to_string(scan.hit_values.size()) + " values for " +
            std::to_string(scan.hits.size()) + " returns");
    if (!scan.hit_value_stds.empty() && scan.hit_value_stds.size() != scan.hit_values.size())
        throw std::invalid_argument(
            "PropertyLayer::insert: " + std::to_string(scan.hit_value_stds.size()) + " value stds for " +
            std::to_string(scan.hit_values.size()) + " values");
    // Check everything first: a bad value must not leave the layer half updated.
    for (size_t i = 0; i < scan.hits.size(); ++i)
    {
        const double s = scan.hit_value_stds.empty() ? options_.default_value_std : scan.hit_value_stds[i];
        if (!std::isfinite(scan.hit_values[i]) || !(s > 0) || !std::isfinite(s) || !scan.hits[i].allFinite())
            throw std::invalid_argument(
                "PropertyLayer::insert: return " + std::to_string(i) + " has value " +
                std::to_string(scan.hit_values[i]) + ", std " + std::to_string(s) +
                " (need a finite value and a finite std > 0)");
    }
    for (size_t i = 0; i < scan.hits.size(); ++i)
        fuse(scan.hits[i], scan.hit_values[i],
             scan.hit_value_stds.empty() ? options_.default_value_std : scan.hit_value_stds[i]);
}

const PropertyLayer::Cell* PropertyLayer::cellAt(const Eigen::Vector2d& p_ref) const
{
    const auto it = cells_.find(keyOf(p_ref));
    return it == cells_.end() ? nullptr : &it->second;
}

std::optional<PropertyLayer::Estimate> PropertyLayer::estimateAt(const Eigen::Vector2d& p_ref) const
{
    const Cell* c = cellAt(p_ref);
    if (!c) return std::nullopt;
    return Estimate{c->weighted / c->info, 1.0 / c->info, c->count};
}

size_t PropertyLayer::memoryBytes() const
{
    // unordered_map node: key, value, next pointer, cached hash; plus the bucket array.
    return sizeof(*this) + cells_.size() * (sizeof(std::int64_t) + sizeof(Cell) + 2 * sizeof(void*)) +
           cells_.bucket_count() * sizeof(void*);
}

void PropertyLayer::renderInto(
    const hymm::ltr::AffineRegionMap& reference_to_current, mrpt::maps::CMetricMap& out) const
{
    auto* hg = dynamic_cast<mrpt::maps::CHeightGridMap2D*>(&out);
    if (!hg)
        throw std::invalid_argument(
            std::string("PropertyLayer::renderInto: cannot draw a property grid into a ") +
            out.GetRuntimeClass()->className);
    hymm::ltr::TriangleFrame::Vertices cur;
    for (size_t k = 0; k < 3; ++k) cur[k] = reference_to_current.mapPoint(reference_[k]);
    const double res = hg->getResolution();
    const CellRange r = rangeOver(
        cur, Eigen::Vector2d(hg->getXMin(), hg->getYMin()), res, static_cast<int>(hg->getSizeX()),
        static_cast<int>(hg->getSizeY()));
    for (int cy = r.y0; cy <= r.y1; ++cy)
        for (int cx = r.x0; cx <= r.x1; ++cx)
        {
            const Eigen::Vector2d c(hg->idx2x(cx), hg->idx2y(cy));
            if (!triangleContains(cur, c, kRenderEdgeTol)) continue;
            const Cell* local = cellAt(reference_to_current.inverseMapPoint(c));
            if (!local) continue;
            mrpt::maps::THeightGridmapCell* cell = hg->cellByIndex(static_cast<unsigned>(cx), static_cast<unsigned>(cy));
            if (!cell) continue;
            cell->h = static_cast<float>(local->weighted / local->info);
            cell->var = static_cast<float>(std::sqrt(1.0 / local->info));
            cell->u = cell->h;
            cell->w = local->count;
        }
}

void PropertyLayer::renderFields(
    const hymm::ltr::AffineRegionMap& reference_to_current, ScalarField& mean, ScalarField* stddev) const
{
    if (stddev && (stddev->sizeX() != mean.sizeX() || stddev->sizeY() != mean.sizeY()))
        throw std::invalid_argument("PropertyLayer::renderFields: mean and stddev fields differ in size");
    hymm::ltr::TriangleFrame::Vertices cur;
    for (size_t k = 0; k < 3; ++k) cur[k] = reference_to_current.mapPoint(reference_[k]);
    const CellRange r = rangeOver(cur, mean.origin, mean.resolution, mean.sizeX(), mean.sizeY());
    for (int iy = r.y0; iy <= r.y1; ++iy)
        for (int ix = r.x0; ix <= r.x1; ++ix)
        {
            const Eigen::Vector2d c = mean.cellCentre(ix, iy);
            if (!triangleContains(cur, c, kRenderEdgeTol)) continue;
            const Cell* local = cellAt(reference_to_current.inverseMapPoint(c));
            if (!local) continue;
            mean.values(iy, ix) = local->weighted / local->info;
            if (stddev) stddev->values(iy, ix) = std::sqrt(1.0 / local->info);
        }
}

void PropertyLayer::save(std::ostream& out) const
{
    // Sorted by key so that equal content gives equal text (hash order is arbitrary).
    const std::map<std::int64_t, Cell> sorted(cells_.begin(), cells_.end());
    out << "property " << sorted.size() << '\n' << std::hexfloat;
    for (const auto& [key, c] : sorted) out << key << ' ' << c.info << ' ' << c.weighted << ' ' << c.count << '\n';
    out << std::defaultfloat;
}

void PropertyLayer::load(std::istream& in)
{
    constexpr const char* kWho = "PropertyLayer::load";
    const size_t n = text_io::readHeader(in, "property", kWho);
    std::unordered_map<std::int64_t, Cell> cells;
    for (size_t i = 0; i < n; ++i)
    {
        std::int64_t key = 0;
        if (!(in >> key)) throw std::runtime_error(std::string(kWho) + ": bad key of cell " + std::to_string(i));
        Cell c;
        c.info = text_io::readNumber(in, kWho);
        c.weighted = text_io::readNumber(in, kWho);
        if (!(in >> c.count) || !(c.info > 0) || !std::isfinite(c.info) || !std::isfinite(c.weighted) || c.count == 0)
            throw std::runtime_error(std::string(kWho) + ": bad cell " + std::to_string(i));
        if (!cells.emplace(key, c).second)
            throw std::runtime_error(std::string(kWho) + ": cell key " + std::to_string(key) + " twice");
    }
    cells_ = std::move(cells);
}

}  // namespace hymm::dense
