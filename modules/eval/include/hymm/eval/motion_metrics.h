/**
 * @file motion_metrics.h
 * @brief Precision and recall of a motion layer against the simulator's truth
 *        (thesis Sec. 6.3.3).
 *
 * Both the detection (a motion layer drawn into a global grid) and the truth (areas from
 * hymm::sim::motion_truth.h rasterised onto the same grid) are CellMasks. A detected
 * cell counts as correct when a truth cell lies within `tolerance` cells of it (the grid
 * quantisation and the range noise move a return by a cell or so); a truth cell counts
 * as found when a detected cell lies within `tolerance` of it.
 */
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace hymm::eval
{
/** A binary grid over the plane (row-major, cell (0, 0) at `origin`). */
struct CellMask
{
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();
    double cell = 0.1;
    int nx = 0, ny = 0;
    std::vector<std::uint8_t> bits;

    CellMask() = default;
    CellMask(const Eigen::Vector2d& origin, double cell, int nx, int ny);
    /** Empty mask on the geometry of `g`. */
    static CellMask like(const mrpt::maps::COccupancyGridMap2D& g);
    /** Cells of `g` with P(occupied) >= min_prob. */
    static CellMask fromGrid(const mrpt::maps::COccupancyGridMap2D& g, float min_prob);

    bool cellOf(const Eigen::Vector2d& p, int& ix, int& iy) const;
    Eigen::Vector2d centre(int ix, int iy) const;
    bool get(int ix, int iy) const { return bits[idx(ix, iy)] != 0; }
    void set(int ix, int iy, bool on = true) { bits[idx(ix, iy)] = on ? 1 : 0; }
    size_t count() const;

    /** Sets the cell holding `p` (ignored outside). */
    void markPoint(const Eigen::Vector2d& p);
    /** Sets every cell whose centre lies inside the polygon (any orientation). */
    void fillPolygon(const std::vector<Eigen::Vector2d>& poly);
    /** Sets every cell whose centre lies within `half_width` of the polygon's boundary. */
    void markOutline(const std::vector<Eigen::Vector2d>& poly, double half_width);
    /** Cells within `r` cells (Chebyshev) of a set cell. */
    CellMask dilated(int r) const;
    /** Cells set in both (same geometry; throws std::invalid_argument otherwise). */
    CellMask intersect(const CellMask& o) const;
    CellMask unite(const CellMask& o) const;
    CellMask minus(const CellMask& o) const;

private:
    size_t idx(int ix, int iy) const
    {
        return static_cast<size_t>(iy) * static_cast<size_t>(nx) + static_cast<size_t>(ix);
    }
    void checkSame(const CellMask& o) const;
};

/** Precision / recall of a detection against a truth (see file comment). */
struct DetectionScore
{
    size_t detected = 0;        //!< cells detected
    size_t truth = 0;           //!< truth cells
    size_t detected_correct = 0;  //!< detected within tolerance of the truth
    size_t truth_found = 0;       //!< truth within tolerance of a detection
    double precision = 0;  //!< detected_correct / detected (1 if nothing detected)
    double recall = 0;     //!< truth_found / truth (1 if no truth)
};
DetectionScore scoreDetection(const CellMask& detected, const CellMask& truth, int tolerance);

/** Cells of `detected` within `tolerance` of a cell of `region` (e.g. the outline of
 *  a static object: false positives there). */
size_t countNear(const CellMask& detected, const CellMask& region, int tolerance);

}  // namespace hymm::eval
