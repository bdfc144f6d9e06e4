/**
 * @file ScalarField.h
 * @brief A plain regular grid of doubles in the global frame: the rendering target of
 *        the SOG surface (Fig. 4.12 b) and of property means / stds (PNG colour maps).
 *
 * Unlike mrpt::maps::COccupancyGridMap2D it stores exact doubles (values may exceed 1
 * and may be NaN for "no data"), so rendered surfaces can be summed across regions.
 */
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hymm::dense
{
struct ScalarField
{
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();  //!< lower-left corner of cell (0, 0)
    double resolution = 0.1;                           //!< [m] cell side
    Eigen::MatrixXd values;                            //!< values(iy, ix)

    /** Smallest field of `resolution` covering [lo, hi], every cell at `fill`. */
    static ScalarField covering(
        const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double resolution, double fill)
    {
        if (!(resolution > 0) || !lo.allFinite() || !hi.allFinite())
            throw std::invalid_argument("ScalarField::covering: resolution must be > 0 and the box finite");
        const auto cells = [&](double extent) {
            return std::max(1, static_cast<int>(std::ceil(extent / resolution - 1e-9)));
        };
        ScalarField f;
        f.origin = lo;
        f.resolution = resolution;
        f.values = Eigen::MatrixXd::Constant(cells(hi.y() - lo.y()), cells(hi.x() - lo.x()), fill);
        return f;
    }

    int sizeX() const { return static_cast<int>(values.cols()); }
    int sizeY() const { return static_cast<int>(values.rows()); }
    Eigen::Vector2d cellCentre(int ix, int iy) const
    {
        return origin + resolution * Eigen::Vector2d(ix + 0.5, iy + 0.5);
    }
    /** Cell holding `p`; false outside. */
    bool cellOf(const Eigen::Vector2d& p, int& ix, int& iy) const
    {
        const double gx = (p.x() - origin.x()) / resolution, gy = (p.y() - origin.y()) / resolution;
        if (!(gx >= 0 && gy >= 0 && gx < sizeX() && gy < sizeY())) return false;
        ix = static_cast<int>(gx);
        iy = static_cast<int>(gy);
        return true;
    }
    /** Value at the cell holding `p`, NaN outside. */
    double at(const Eigen::Vector2d& p) const
    {
        int ix, iy;
        return cellOf(p, ix, iy) ? values(iy, ix) : std::nan("");
    }
};

}  // namespace hymm::dense
