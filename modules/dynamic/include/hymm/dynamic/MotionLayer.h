/**
 * @file MotionLayer.h
 * @brief One binary motion layer of one region (thesis Sec. 6.3.1-6.3.2).
 *
 * A grid of flags in the coordinates of the region's reference triangle, on the
 * geometry of the region's occupancy grid when the layer was created. Local coordinates
 * never change after a correction; rendering maps them through the region's
 * reference -> current affine map, so a marked area stays on the landmarks it was
 * found among after a loop closure (Sec. 6.3.2).
 */
#pragma once

#include <hymm/ltr/AffineRegionMap.h>
#include <hymm/ltr/TriangleFrame.h>

#include <mrpt/serialization/CArchive.h>

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

namespace hymm::dynamic
{
class MotionLayer
{
public:
    MotionLayer() = default;

    /** True once the geometry is set (first orMask). */
    bool initialised() const { return nx_ > 0; }
    /** ORs a mask given on a grid (origin, cell, nx x ny, row-major) into the layer. The
     *  first call fixes the layer's geometry; a mask on another geometry (the occupancy
     *  grid was coarsened since) is mapped cell centre by cell centre. Returns cells
     *  newly set. */
    size_t orMask(const Eigen::Vector2d& origin, double cell, int nx, int ny,
                  const std::vector<std::uint8_t>& mask);
    /** Flag at a reference-frame point (false outside the grid). */
    bool at(const Eigen::Vector2d& p_ref) const;
    size_t count() const { return count_; }
    int sizeX() const { return nx_; }
    int sizeY() const { return ny_; }
    double cellSize() const { return cell_; }
    const Eigen::Vector2d& origin() const { return origin_; }
    bool cell(int ix, int iy) const { return bits_[static_cast<size_t>(iy) * nx_ + ix] != 0; }
    Eigen::Vector2d cellCentre(int ix, int iy) const
    {
        return origin_ + Eigen::Vector2d((ix + 0.5) * cell_, (iy + 0.5) * cell_);
    }
    size_t memoryBytes() const { return sizeof(*this) + bits_.capacity(); }

    /** The layer bit for bit, for a saved run (core/state_archive.h). */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

private:
    Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
    double cell_ = 0;
    int nx_ = 0, ny_ = 0;
    std::vector<std::uint8_t> bits_;
    size_t count_ = 0;
};

}  // namespace hymm::dynamic
