#include "hymm/eval/motion_metrics.h"

#include <hymm/dense/geometry.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hymm::eval
{
CellMask::CellMask(const Eigen::Vector2d& o, double c, int x, int y)
    : origin(o), cell(c), nx(x), ny(y), bits(static_cast<size_t>(x) * static_cast<size_t>(y), 0)
{
    if (x < 0 || y < 0 || !(c > 0)) throw std::invalid_argument("CellMask: bad geometry");
}

CellMask CellMask::like(const mrpt::maps::COccupancyGridMap2D& g)
{
    return CellMask(Eigen::Vector2d(g.getXMin(), g.getYMin()), g.getResolution(),
                    static_cast<int>(g.getSizeX()), static_cast<int>(g.getSizeY()));
}

CellMask CellMask::fromGrid(const mrpt::maps::COccupancyGridMap2D& g, float min_prob)
{
    CellMask m = like(g);
    for (int iy = 0; iy < m.ny; ++iy)
        for (int ix = 0; ix < m.nx; ++ix)
            if (g.getCell(ix, iy) >= min_prob) m.set(ix, iy);
    return m;
}

bool CellMask::cellOf(const Eigen::Vector2d& p, int& ix, int& iy) const
{
    ix = static_cast<int>(std::floor((p.x() - origin.x()) / cell));
    iy = static_cast<int>(std::floor((p.y() - origin.y()) / cell));
    return ix >= 0 && iy >= 0 && ix < nx && iy < ny;
}

Eigen::Vector2d CellMask::centre(int ix, int iy) const
{
    return origin + Eigen::Vector2d((ix + 0.5) * cell, (iy + 0.5) * cell);
}

size_t CellMask::count() const
{
    return static_cast<size_t>(std::count(bits.begin(), bits.end(), std::uint8_t{1}));
}

void CellMask::markPoint(const Eigen::Vector2d& p)
{
    int ix, iy;
    if (cellOf(p, ix, iy)) set(ix, iy);
}

namespace
{
bool inside(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& poly)
{
    bool in = false;
    for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
    {
        const auto &a = poly[i], &b = poly[j];
        if ((a.y() > p.y()) != (b.y() > p.y()) &&
            p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
            in = !in;
    }
    return in;
}
}  // namespace

void CellMask::fillPolygon(const std::vector<Eigen::Vector2d>& poly)
{
    if (poly.size() < 3) return;
    Eigen::Vector2d lo = poly[0], hi = poly[0];
    for (const auto& v : poly)
    {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
    int x0, y0, x1, y1;
    cellOf(lo, x0, y0);
    cellOf(hi, x1, y1);
    for (int iy = std::max(0, y0); iy <= std::min(ny - 1, y1); ++iy)
        for (int ix = std::max(0, x0); ix <= std::min(nx - 1, x1); ++ix)
            if (inside(centre(ix, iy), poly)) set(ix, iy);
}

void CellMask::markOutline(const std::vector<Eigen::Vector2d>& poly, double half_width)
{
    if (poly.size() < 2) return;
    Eigen::Vector2d lo = poly[0], hi = poly[0];
    for (const auto& v : poly)
    {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
    lo -= Eigen::Vector2d::Constant(half_width);
    hi += Eigen::Vector2d::Constant(half_width);
    int x0, y0, x1, y1;
    cellOf(lo, x0, y0);
    cellOf(hi, x1, y1);
    for (int iy = std::max(0, y0); iy <= std::min(ny - 1, y1); ++iy)
        for (int ix = std::max(0, x0); ix <= std::min(nx - 1, x1); ++ix)
        {
            const Eigen::Vector2d c = centre(ix, iy);
            for (size_t i = 0; i < poly.size(); ++i)
                if (dense::distanceToSegment(c, poly[i], poly[(i + 1) % poly.size()]) <= half_width)
                {
                    set(ix, iy);
                    break;
                }
        }
}

CellMask CellMask::dilated(int r) const
{
    CellMask out(origin, cell, nx, ny);
    for (int iy = 0; iy < ny; ++iy)
        for (int ix = 0; ix < nx; ++ix)
        {
            if (!get(ix, iy)) continue;
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx)
                {
                    const int x = ix + dx, y = iy + dy;
                    if (x >= 0 && y >= 0 && x < nx && y < ny) out.set(x, y);
                }
        }
    return out;
}

void CellMask::checkSame(const CellMask& o) const
{
    if (nx != o.nx || ny != o.ny || std::abs(cell - o.cell) > 1e-12 || (origin - o.origin).norm() > 1e-9)
        throw std::invalid_argument("CellMask: masks on different grids");
}

CellMask CellMask::intersect(const CellMask& o) const
{
    checkSame(o);
    CellMask out = *this;
    for (size_t k = 0; k < bits.size(); ++k) out.bits[k] = bits[k] && o.bits[k];
    return out;
}

CellMask CellMask::unite(const CellMask& o) const
{
    checkSame(o);
    CellMask out = *this;
    for (size_t k = 0; k < bits.size(); ++k) out.bits[k] = bits[k] || o.bits[k];
    return out;
}

CellMask CellMask::minus(const CellMask& o) const
{
    checkSame(o);
    CellMask out = *this;
    for (size_t k = 0; k < bits.size(); ++k) out.bits[k] = bits[k] && !o.bits[k];
    return out;
}

DetectionScore scoreDetection(const CellMask& detected, const CellMask& truth, int tolerance)
{
    DetectionScore s;
    s.detected = detected.count();
    s.truth = truth.count();
    s.detected_correct = detected.intersect(truth.dilated(tolerance)).count();
    s.truth_found = truth.intersect(detected.dilated(tolerance)).count();
    s.precision = s.detected ? static_cast<double>(s.detected_correct) / static_cast<double>(s.detected) : 1.0;
    s.recall = s.truth ? static_cast<double>(s.truth_found) / static_cast<double>(s.truth) : 1.0;
    return s;
}

size_t countNear(const CellMask& detected, const CellMask& region, int tolerance)
{
    return detected.intersect(region.dilated(tolerance)).count();
}

}  // namespace hymm::eval
