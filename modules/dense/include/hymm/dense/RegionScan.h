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

#include <limits>
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
    /** Far end of the WHOLE beam (the return when `beam_hit`, else the point at max
     *  range), reference coordinates; NaN when unknown (rays built by hand), in which
     *  case layers take `to` as the return if `ends_at_hit` and as a free end if not. */
    Eigen::Vector2d beam_end = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
    bool beam_hit = false;  //!< the whole beam ended in a return (valid with beam_end)
};

struct RegionScan
{
    /** Returns owned by this region (each return is owned by exactly one region). */
    std::vector<Eigen::Vector2d> hits;
    /** Beam pieces inside this region's triangle. */
    std::vector<FreeRay> rays;
    /** Returns of the same scan that lie BEFORE this region, on beams whose line goes
     *  on into it (near its triangle): the region is hidden behind them. Their beams
     *  give no free space here; the particle layer's free-space protection needs them
     *  (a surface behind a nearer return keeps its weight). HybridMetricMap fills them
     *  only when a particle layer with free_space_protection is enabled. */
    std::vector<Eigen::Vector2d> shadow_returns;
    /** Sensor position at observation time (may lie outside the triangle). */
    Eigen::Vector2d sensor = Eigen::Vector2d::Zero();

    /** Optional per-return scalar (intensity, elevation, ...), parallel to `hits`; empty
     *  when the scan carries none. */
    std::vector<double> hit_values;
    /** Optional 1-sigma of `hit_values`, parallel to it; empty = the layer's default. */
    std::vector<double> hit_value_stds;

    /** Range / bearing noise of the returns [m], [rad]; 0 = unknown (layers then use
     *  their configured noise). */
    double range_std_m = 0.0;
    double bearing_std_rad = 0.0;
    /** Linear part of the current -> reference map of the region (A^{-1} for
     *  current = A reference + t). Noise and bearings are defined in the current
     *  (metric, global) frame; layers map covariances and sample offsets with it.
     *  Identity when the region has not moved. */
    Eigen::Matrix2d to_reference_linear = Eigen::Matrix2d::Identity();

    bool empty() const { return hits.empty() && rays.empty(); }
};

}  // namespace hymm::dense
