#include "hymm/dense/LogOddsGrid.h"

#include <algorithm>
#include <cmath>
#include <istream>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string>

namespace hymm::dense
{
LogOddsGrid::LogOddsGrid(
    const Eigen::Vector2d& origin, int size_x, int size_y, double cell_size, float initial)
    : origin_(origin), size_x_(size_x), size_y_(size_y), cell_size_(cell_size), initial_(initial)
{
    if (size_x <= 0 || size_y <= 0 || !(cell_size > 0))
        throw std::invalid_argument(
            "LogOddsGrid: size " + std::to_string(size_x) + "x" + std::to_string(size_y) +
            " with cell " + std::to_string(cell_size) + " m is empty");
    const size_t n = static_cast<size_t>(size_x) * static_cast<size_t>(size_y);
    l_.assign(n, initial);
    flags_.assign(n, kUpdatable);
}

LogOddsGrid LogOddsGrid::covering(
    const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double cell_size, float initial)
{
    const auto cells = [&](double extent) {
        return std::max(1, static_cast<int>(std::ceil(extent / cell_size - 1e-9)));
    };
    return LogOddsGrid(lo, cells(hi.x() - lo.x()), cells(hi.y() - lo.y()), cell_size, initial);
}

bool LogOddsGrid::cellOf(const Eigen::Vector2d& p, int& ix, int& iy) const
{
    const double gx = (p.x() - origin_.x()) / cell_size_;
    const double gy = (p.y() - origin_.y()) / cell_size_;
    if (!(gx >= 0 && gy >= 0 && gx < size_x_ && gy < size_y_)) return false;
    ix = static_cast<int>(gx);
    iy = static_cast<int>(gy);
    return true;
}

Eigen::Vector2d LogOddsGrid::cellMin(int ix, int iy) const
{
    return origin_ + cell_size_ * Eigen::Vector2d(ix, iy);
}

Eigen::Vector2d LogOddsGrid::cellCentre(int ix, int iy) const
{
    return origin_ + cell_size_ * Eigen::Vector2d(ix + 0.5, iy + 0.5);
}

void LogOddsGrid::setUpdatable(int ix, int iy, bool on)
{
    auto& f = flags_[index(ix, iy)];
    f = on ? (f | kUpdatable) : (f & static_cast<std::uint8_t>(~kUpdatable));
}

// Inline (only this file calls it): it runs once per cell a beam crosses, the innermost
// loop of the dense step.
inline void LogOddsGrid::mark(int ix, int iy, std::uint8_t bit)
{
    if (ix < 0 || iy < 0 || ix >= size_x_ || iy >= size_y_) return;
    const size_t i = index(ix, iy);
    std::uint8_t& f = flags_[i];
    if (!(f & kUpdatable)) return;
    if (!(f & (kFree | kOccupied))) touched_.push_back(i);
    f |= bit;
}

void LogOddsGrid::markOccupied(const Eigen::Vector2d& p)
{
    int ix, iy;
    if (cellOf(p, ix, iy)) mark(ix, iy, kOccupied);
}

void LogOddsGrid::markFree(const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool exclude_end_cell)
{
    // Amanatides & Woo voxel traversal in cell units.
    const Eigen::Vector2d g0 = (from - origin_) / cell_size_;
    const Eigen::Vector2d g1 = (to - origin_) / cell_size_;
    const Eigen::Vector2d d = g1 - g0;
    int ix = static_cast<int>(std::floor(g0.x())), iy = static_cast<int>(std::floor(g0.y()));
    const int ex = static_cast<int>(std::floor(g1.x())), ey = static_cast<int>(std::floor(g1.y()));
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const int step_x = d.x() > 0 ? 1 : -1, step_y = d.y() > 0 ? 1 : -1;
    const double dt_x = d.x() != 0 ? 1.0 / std::abs(d.x()) : kInf;
    const double dt_y = d.y() != 0 ? 1.0 / std::abs(d.y()) : kInf;
    double t_x = d.x() > 0 ? (ix + 1 - g0.x()) * dt_x : d.x() < 0 ? (g0.x() - ix) * dt_x : kInf;
    double t_y = d.y() > 0 ? (iy + 1 - g0.y()) * dt_y : d.y() < 0 ? (g0.y() - iy) * dt_y : kInf;
    // The cell count of a straight traversal is bounded by the Manhattan distance; the
    // bound guards against rounding making the walk miss the end cell.
    int remaining = std::abs(ex - ix) + std::abs(ey - iy);
    for (;;)
    {
        const bool at_end = ix == ex && iy == ey;
        if (!(at_end && exclude_end_cell)) mark(ix, iy, kFree);
        if (at_end || remaining-- <= 0) break;
        if (t_x < t_y)
        {
            t_x += dt_x;
            ix += step_x;
        }
        else
        {
            t_y += dt_y;
            iy += step_y;
        }
    }
}

size_t LogOddsGrid::applyMarks(float l_free, float l_occ, float l_min, float l_max)
{
    for (const size_t i : touched_)
    {
        const float inc = (flags_[i] & kOccupied) ? l_occ : l_free;
        l_[i] = std::clamp(l_[i] + inc, l_min, l_max);
        flags_[i] &= static_cast<std::uint8_t>(~(kFree | kOccupied));
    }
    const size_t n = touched_.size();
    touched_.clear();
    return n;
}

size_t LogOddsGrid::changedCells() const
{
    return static_cast<size_t>(
        std::count_if(l_.begin(), l_.end(), [this](float v) { return v != initial_; }));
}

size_t LogOddsGrid::memoryBytes() const
{
    return sizeof(*this) + l_.capacity() * sizeof(float) + flags_.capacity() +
           touched_.capacity() * sizeof(size_t);
}

void LogOddsGrid::save(std::ostream& out) const
{
    // Values as hex floats: exact round trip.
    out << "grid " << std::hexfloat << origin_.x() << ' ' << origin_.y() << ' ' << cell_size_
        << ' ' << initial_ << std::defaultfloat << ' ' << size_x_ << ' ' << size_y_ << '\n';
    out << std::hexfloat;
    for (size_t i = 0; i < l_.size(); ++i)
        out << l_[i] << ' ' << int(flags_[i] & kUpdatable) << (i + 1 == l_.size() ? '\n' : ' ');
    out << std::defaultfloat;
}

namespace
{
double readHexDouble(std::istream& in)
{
    std::string tok;
    if (!(in >> tok)) throw std::runtime_error("LogOddsGrid::load: unexpected end of stream");
    try
    {
        size_t used = 0;
        const double v = std::stod(tok, &used);
        if (used != tok.size()) throw std::invalid_argument(tok);
        return v;
    }
    catch (const std::exception&)
    {
        throw std::runtime_error("LogOddsGrid::load: bad number '" + tok + "'");
    }
}
}  // namespace

LogOddsGrid LogOddsGrid::load(std::istream& in)
{
    std::string tag;
    if (!(in >> tag) || tag != "grid")
        throw std::runtime_error("LogOddsGrid::load: expected 'grid', got '" + tag + "'");
    const double ox = readHexDouble(in), oy = readHexDouble(in);
    const double cell = readHexDouble(in);
    const auto initial = static_cast<float>(readHexDouble(in));
    int sx = 0, sy = 0;
    if (!(in >> sx >> sy)) throw std::runtime_error("LogOddsGrid::load: bad grid size");
    LogOddsGrid g(Eigen::Vector2d(ox, oy), sx, sy, cell, initial);
    for (size_t i = 0; i < g.l_.size(); ++i)
    {
        g.l_[i] = static_cast<float>(readHexDouble(in));
        int upd = 0;
        if (!(in >> upd) || (upd != 0 && upd != 1))
            throw std::runtime_error("LogOddsGrid::load: bad updatable flag at cell " + std::to_string(i));
        g.flags_[i] = upd ? kUpdatable : 0;
    }
    return g;
}

}  // namespace hymm::dense
