#include "hymm/dense/PointsLayer.h"

#include "region_seed.h"

#include <hymm/core/config_utils.h>
#include <hymm/dense/geometry.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <istream>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <vector>

namespace hymm::dense
{
namespace
{
/** splitmix64 (Steele, Lea, Flood 2014) over an external 8-byte state: a uniform random
 *  bit generator small enough to keep one per region. */
struct SplitMix64
{
    using result_type = std::uint64_t;
    std::uint64_t& state;
    static constexpr result_type min() { return 0; }
    static constexpr result_type max() { return ~result_type{0}; }
    result_type operator()()
    {
        std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
};
}  // namespace

hymm::core::OptionTable PointsLayer::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("voxel_size_m", voxel_size_m, "m", between(0, 100), "keep one point per voxel; 0 = keep every return");
    t.integer("max_points", max_points, "", 0, 100000000,
              "returns kept per region at most, a uniform sample of all it received (reservoir sampling); "
              "0 = no cap by count (with max_points_per_cell = 0 too: every return, thesis Sec. 3.9)");
    t.integer("random_seed", random_seed, "", 0, 2147483647, "mixed with the region's vertices (reservoir sampling)");
    t.real("max_points_per_cell", max_points_per_cell, "", between(0, 1e6),
           "the sample is also held to this many points per occupied cell of side area_cell_m (a bound by area); "
           "0 = max_points alone");
    t.real("area_cell_m", area_cell_m, "m", between(0.001, 100), "cell of the bound by area");
    return t;
}

void PointsLayer::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void PointsLayer::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void PointsLayer::Options::validate(const std::string& s) const
{
    if (!(voxel_size_m >= 0))
        hymm::core::throwConfigError(s, "voxel_size_m", std::to_string(voxel_size_m), "must be >= 0");
    if (max_points < 0) hymm::core::throwConfigError(s, "max_points", std::to_string(max_points), "must be >= 0");
    if (!(max_points_per_cell >= 0) || !std::isfinite(max_points_per_cell))
        hymm::core::throwConfigError(s, "max_points_per_cell", std::to_string(max_points_per_cell),
                                     "must be finite and >= 0");
    if (!(area_cell_m > 0) || !std::isfinite(area_cell_m))
        hymm::core::throwConfigError(s, "area_cell_m", std::to_string(area_cell_m), "must be finite and > 0");
}

PointsLayer::PointsLayer(const Options& options)
    : PointsLayer(options, {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()})
{
}

PointsLayer::PointsLayer(const Options& options, const hymm::ltr::TriangleFrame::Vertices& reference)
    : options_(options)
{
    options_.validate();
    const auto seed = detail::regionSeedWords(static_cast<std::uint32_t>(options_.random_seed), reference);
    std::seed_seq seq(seed.begin(), seed.end());
    std::uint32_t words[2];
    seq.generate(words, words + 2);
    rng_ = (static_cast<std::uint64_t>(words[0]) << 32) | words[1];
}

bool PointsLayer::acceptVoxel(const Eigen::Vector2d& p)
{
    if (options_.voxel_size_m <= 0) return true;
    // 32-bit cell indices packed into one key; +-2^31 voxels covers any region.
    const auto ix = static_cast<std::int64_t>(std::floor(p.x() / options_.voxel_size_m));
    const auto iy = static_cast<std::int64_t>(std::floor(p.y() / options_.voxel_size_m));
    return voxels_.insert(packCellKey(ix, iy)).second;
}

size_t PointsLayer::limit() const
{
    const auto cap = static_cast<size_t>(options_.max_points);
    if (options_.max_points_per_cell <= 0 || area_limit_ == 0) return cap;
    return cap == 0 ? area_limit_ : std::min(cap, area_limit_);
}

void PointsLayer::updateAreaLimit()
{
    const auto& xs = points_.getPointsBufferRef_x();
    const auto& ys = points_.getPointsBufferRef_y();
    if (xs.empty())  // nothing to count: no bound yet
    {
        area_limit_ = 0;
        next_area_check_ = offered_ + 16;
        return;
    }
    std::vector<std::int64_t> cells(xs.size());
    for (size_t i = 0; i < xs.size(); ++i)
        cells[i] = pointCellKey(Eigen::Vector2d(xs[i], ys[i]), options_.area_cell_m);
    std::sort(cells.begin(), cells.end());
    const auto occupied = static_cast<double>(std::unique(cells.begin(), cells.end()) - cells.begin());
    area_limit_ = std::max<size_t>(1, static_cast<size_t>(std::floor(options_.max_points_per_cell * occupied)));
    // Counted again once as many returns as the sample holds were offered: the count
    // costs O(n log n), so O(log n) a return.
    next_area_check_ = offered_ + std::max<size_t>(points_.size(), 16);
    const size_t keep = limit();
    if (keep == 0 || points_.size() <= keep) return;
    // Uniformly chosen points leave (swap with the last, drop it): what stays is a
    // uniform sample of the sample, so of every return.
    SplitMix64 gen{rng_};
    size_t n = points_.size();
    while (n > keep)
    {
        const size_t j = std::uniform_int_distribution<size_t>(0, n - 1)(gen);
        --n;
        if (j != n) points_.setPoint(j, xs[n], ys[n], 0.0f);
    }
    points_.resize(n);
}

void PointsLayer::insertPoints(const std::vector<Eigen::Vector2d>& points_ref)
{
    for (const auto& p : points_ref)
    {
        if (!acceptVoxel(p)) continue;
        ++offered_;
        if (options_.max_points_per_cell > 0 && offered_ >= next_area_check_) updateAreaLimit();
        const size_t cap = limit();
        const size_t n = points_.size();
        // Every return so far kept: store it while there is room.
        if (cap == 0 || (n < cap && offered_ == n + 1))
        {
            points_.insertPoint(static_cast<float>(p.x()), static_cast<float>(p.y()));
            continue;
        }
        // Algorithm R: the offered_-th return is kept with probability cap / offered_,
        // j uniform in [0, offered_): in slot j if the sample is full, appended if the
        // bound by area has grown since it was full.
        SplitMix64 gen{rng_};
        const size_t j = std::uniform_int_distribution<size_t>(0, offered_ - 1)(gen);
        if (j >= cap) continue;
        if (n < cap)
            points_.insertPoint(static_cast<float>(p.x()), static_cast<float>(p.y()));
        else
            points_.setPoint(j, static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f);
    }
}

void PointsLayer::insert(const RegionScan& scan) { insertPoints(scan.hits); }

size_t PointsLayer::memoryBytes() const
{
    return sizeof(*this) + points_.size() * 3 * sizeof(float) +
           voxels_.size() * (sizeof(std::int64_t) + 2 * sizeof(void*));
}

void PointsLayer::renderInto(
    const hymm::ltr::AffineRegionMap& reference_to_current, mrpt::maps::CMetricMap& out) const
{
    auto* pts = dynamic_cast<mrpt::maps::CPointsMap*>(&out);
    if (!pts)
        throw std::invalid_argument(
            std::string("PointsLayer::renderInto: cannot draw points into a ") +
            out.GetRuntimeClass()->className);
    const auto& xs = points_.getPointsBufferRef_x();
    const auto& ys = points_.getPointsBufferRef_y();
    for (size_t i = 0; i < xs.size(); ++i)
    {
        const Eigen::Vector2d p = reference_to_current.mapPoint(Eigen::Vector2d(xs[i], ys[i]));
        pts->insertPoint(static_cast<float>(p.x()), static_cast<float>(p.y()));
    }
}

void PointsLayer::save(std::ostream& out) const
{
    const auto& xs = points_.getPointsBufferRef_x();
    const auto& ys = points_.getPointsBufferRef_y();
    out << "points " << xs.size() << '\n';
    const auto old = out.precision(std::numeric_limits<float>::max_digits10);
    for (size_t i = 0; i < xs.size(); ++i) out << xs[i] << ' ' << ys[i] << '\n';
    out.precision(old);
}

void PointsLayer::load(std::istream& in)
{
    std::string tag;
    size_t n = 0;
    if (!(in >> tag >> n) || tag != "points")
        throw std::runtime_error("PointsLayer::load: expected 'points <count>'");
    points_.clear();
    voxels_.clear();
    for (size_t i = 0; i < n; ++i)
    {
        float x = 0, y = 0;
        if (!(in >> x >> y))
            throw std::runtime_error("PointsLayer::load: bad point " + std::to_string(i) + " of " + std::to_string(n));
        points_.insertPoint(x, y);
        acceptVoxel(Eigen::Vector2d(x, y));
    }
    offered_ = points_.size();
    area_limit_ = 0;
    next_area_check_ = 0;  // counted at the next insert
}

}  // namespace hymm::dense
