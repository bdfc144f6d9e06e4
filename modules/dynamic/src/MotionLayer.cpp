#include "hymm/dynamic/MotionLayer.h"

#include <cmath>
#include <stdexcept>

namespace hymm::dynamic
{
size_t MotionLayer::orMask(const Eigen::Vector2d& origin, double cell, int nx, int ny,
                           const std::vector<std::uint8_t>& mask)
{
    if (nx <= 0 || ny <= 0 || !(cell > 0) ||
        mask.size() != static_cast<size_t>(nx) * static_cast<size_t>(ny))
        throw std::invalid_argument("MotionLayer::orMask: mask does not match its geometry");
    if (!initialised())
    {
        origin_ = origin;
        cell_ = cell;
        nx_ = nx;
        ny_ = ny;
        bits_.assign(mask.size(), 0);
    }
    size_t added = 0;
    const bool same = (origin - origin_).norm() < 1e-9 && std::abs(cell - cell_) < 1e-12 &&
                      nx == nx_ && ny == ny_;
    for (int iy = 0; iy < ny; ++iy)
        for (int ix = 0; ix < nx; ++ix)
        {
            const size_t k = static_cast<size_t>(iy) * static_cast<size_t>(nx) + static_cast<size_t>(ix);
            if (!mask[k]) continue;
            size_t dst = k;
            if (!same)
            {
                // Another resolution: the layer cell under this mask cell's centre.
                const Eigen::Vector2d c = origin + Eigen::Vector2d((ix + 0.5) * cell, (iy + 0.5) * cell);
                const int jx = static_cast<int>(std::floor((c.x() - origin_.x()) / cell_));
                const int jy = static_cast<int>(std::floor((c.y() - origin_.y()) / cell_));
                if (jx < 0 || jy < 0 || jx >= nx_ || jy >= ny_) continue;
                dst = static_cast<size_t>(jy) * static_cast<size_t>(nx_) + static_cast<size_t>(jx);
            }
            if (!bits_[dst])
            {
                bits_[dst] = 1;
                ++added;
            }
        }
    count_ += added;
    return added;
}

bool MotionLayer::at(const Eigen::Vector2d& p_ref) const
{
    if (!initialised()) return false;
    const int ix = static_cast<int>(std::floor((p_ref.x() - origin_.x()) / cell_));
    const int iy = static_cast<int>(std::floor((p_ref.y() - origin_.y()) / cell_));
    if (ix < 0 || iy < 0 || ix >= nx_ || iy >= ny_) return false;
    return cell(ix, iy);
}

}  // namespace hymm::dynamic
