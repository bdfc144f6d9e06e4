/**
 * @file LikelihoodGrid.h
 * @brief (module-private) The per-point log-likelihood grid of the correlative searches
 *        (CorrelativeMatcher, wideSearch): -min(d^2 / 2 sigma^2, gate^2 / 2), d the
 *        distance to the nearest scan point, bilinear lookup.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "hymm/scanslam/PointSet.h"

namespace hymm::scanslam
{
/** Log-likelihood lookup: -min(d^2 / 2 sigma^2, floor) with d to the nearest scan point. */
class LikelihoodGrid
{
public:
    LikelihoodGrid(const Vec2& lo, const Vec2& hi, double res, double sigma, double gate,
                   const PointSet& scan)
        : lo_(lo), res_(res), floor_(0.5 * gate * gate)
    {
        nx_ = static_cast<int>(std::ceil((hi.x() - lo.x()) / res)) + 2;
        ny_ = static_cast<int>(std::ceil((hi.y() - lo.y()) / res)) + 2;
        cells_.assign(static_cast<size_t>(nx_) * static_cast<size_t>(ny_), -floor_);
        const double reach = gate * sigma;
        const int rc = static_cast<int>(std::ceil(reach / res));
        const double k = 0.5 / (sigma * sigma);
        for (const Vec2& q : scan.points)
        {
            const int cx = static_cast<int>(std::floor((q.x() - lo.x()) / res));
            const int cy = static_cast<int>(std::floor((q.y() - lo.y()) / res));
            if (cx < -rc || cy < -rc || cx >= nx_ + rc || cy >= ny_ + rc) continue;
            for (int y = std::max(0, cy - rc); y <= std::min(ny_ - 1, cy + rc); ++y)
                for (int x = std::max(0, cx - rc); x <= std::min(nx_ - 1, cx + rc); ++x)
                {
                    const Vec2 c(lo.x() + x * res, lo.y() + y * res);
                    const double v = -std::min(k * (c - q).squaredNorm(), floor_);
                    float& cell = cells_[static_cast<size_t>(y) * static_cast<size_t>(nx_) +
                                         static_cast<size_t>(x)];
                    cell = std::max(cell, static_cast<float>(v));
                }
        }
    }

    /** Bilinear interpolation; the floor outside the grid. */
    double at(double px, double py) const
    {
        const double fx = (px - lo_.x()) / res_, fy = (py - lo_.y()) / res_;
        const int x = static_cast<int>(std::floor(fx)), y = static_cast<int>(std::floor(fy));
        if (x < 0 || y < 0 || x + 1 >= nx_ || y + 1 >= ny_) return -floor_;
        const double ax = fx - x, ay = fy - y;
        const size_t i = static_cast<size_t>(y) * static_cast<size_t>(nx_) + static_cast<size_t>(x);
        const size_t n = static_cast<size_t>(nx_);
        return (1 - ay) * ((1 - ax) * cells_[i] + ax * cells_[i + 1]) +
               ay * ((1 - ax) * cells_[i + n] + ax * cells_[i + n + 1]);
    }

    /** The scores of a lattice of translations of `pts`:
     *  out[(ky + ny) (2 nx + 1) + kx + nx] = sum over p of at(p + (cx + kx step, cy + ky step)),
     *  |kx| <= nx, |ky| <= ny. The same arithmetic as calling at() pose by pose, summed
     *  point by point in the same order (so the same scores), but a point's cell column
     *  and weight are found once per lattice column, its row once per lattice row, and
     *  the interpolation along x once per row of cells: the exhaustive searches spent
     *  most of their time in at()'s divisions and floors. */
    void scoreLattice(const std::vector<Vec2>& pts, double cx, double cy, double step, int nx, int ny,
                      std::vector<double>& out) const
    {
        const int sx = 2 * nx + 1, sy = 2 * ny + 1;
        out.assign(static_cast<size_t>(sx) * static_cast<size_t>(sy), 0.0);
        std::vector<double> tx(static_cast<size_t>(sx)), ty(static_cast<size_t>(sy));
        for (int i = 0; i < sx; ++i) tx[static_cast<size_t>(i)] = cx + (i - nx) * step;
        for (int j = 0; j < sy; ++j) ty[static_cast<size_t>(j)] = cy + (j - ny) * step;
        std::vector<int> col(static_cast<size_t>(sx)), row(static_cast<size_t>(sy));
        std::vector<double> ax(static_cast<size_t>(sx)), ay(static_cast<size_t>(sy)), h;
        for (const Vec2& p : pts)
        {
            // Cells as at() finds them: the same expressions, so the same weights.
            bool inside = true;
            for (size_t i = 0; i < tx.size(); ++i)
            {
                const double fx = (p.x() + tx[i] - lo_.x()) / res_;
                col[i] = static_cast<int>(std::floor(fx));
                ax[i] = fx - col[i];
                inside = inside && col[i] >= 0 && col[i] + 1 < nx_;
            }
            for (size_t j = 0; j < ty.size(); ++j)
            {
                const double fy = (p.y() + ty[j] - lo_.y()) / res_;
                row[j] = static_cast<int>(std::floor(fy));
                ay[j] = fy - row[j];
                inside = inside && row[j] >= 0 && row[j] + 1 < ny_;
            }
            if (!inside)
            {
                for (size_t j = 0; j < ty.size(); ++j)
                    for (size_t i = 0; i < tx.size(); ++i) out[j * tx.size() + i] += at(p.x() + tx[i], p.y() + ty[j]);
                continue;
            }
            const auto [rlo, rhi] = std::minmax_element(row.begin(), row.end());
            const int r0 = *rlo, nr = *rhi + 2 - r0;
            h.resize(static_cast<size_t>(nr) * tx.size());
            for (int r = 0; r < nr; ++r)
            {
                const float* c = &cells_[static_cast<size_t>(r0 + r) * static_cast<size_t>(nx_)];
                double* hr = &h[static_cast<size_t>(r) * tx.size()];
                for (size_t i = 0; i < tx.size(); ++i)
                    hr[i] = (1 - ax[i]) * c[col[i]] + ax[i] * c[col[i] + 1];
            }
            for (size_t j = 0; j < ty.size(); ++j)
            {
                const double* h0 = &h[static_cast<size_t>(row[j] - r0) * tx.size()];
                const double* h1 = h0 + tx.size();
                const double a = ay[j];
                double* o = &out[j * tx.size()];
                for (size_t i = 0; i < tx.size(); ++i) o[i] += (1 - a) * h0[i] + a * h1[i];
            }
        }
    }

    double floorValue() const { return -floor_; }

private:
    Vec2 lo_;
    double res_;
    double floor_;
    int nx_ = 0, ny_ = 0;
    std::vector<float> cells_;
};

}  // namespace hymm::scanslam
