/**
 * @file RegionScan.h
 * @brief The part of one laser scan that falls in one region, in that region's
 *        reference-frame coordinates (DESIGN.md "One way to store local maps").
 *
 * HybridMetricMap builds one RegionScan per region the scan touches and fuses it into
 * every layer of that region's LocalDenseMap (multi-layer maps, thesis Sec. 4.5):
 * each layer takes what it needs (returns for point layers, rays for grids).
 */
#pragma once

#include <Eigen/Core>

#include <vector>

namespace hymm::dense
{
/** A beam clipped to the region: free space from `from` to `to`; when `ends_at_hit`
 *  the beam's return lies at `to` (inside this region's closed triangle). */
struct FreeRay
{
    Eigen::Vector2d from;
    Eigen::Vector2d to;
    bool ends_at_hit = false;
};

struct RegionScan
{
    /** Returns owned by this region (each return is owned by exactly one region). */
    std::vector<Eigen::Vector2d> hits;
    /** Beam pieces inside this region's triangle. */
    std::vector<FreeRay> rays;
    /** Sensor position at observation time (may lie outside the triangle). */
    Eigen::Vector2d sensor = Eigen::Vector2d::Zero();

    bool empty() const { return hits.empty() && rays.empty(); }
};

}  // namespace hymm::dense
