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

    double floorValue() const { return -floor_; }

private:
    Vec2 lo_;
    double res_;
    double floor_;
    int nx_ = 0, ny_ = 0;
    std::vector<float> cells_;
};

}  // namespace hymm::scanslam
