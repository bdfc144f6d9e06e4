/**
 * @file dense_gaussians.h
 * @brief The dense map around a place as Gaussians in the global frame: what augments a
 *        scan landmark's template (thesis 6.2: "the dense map surrounding the scan
 *        landmark is recovered and is added to the landmark template").
 */
#pragma once

#include <hymm/dense/HybridMetricMap.h>
#include <hymm/ltr/RegionPartition.h>
#include <hymm/scanslam/PointSet.h>

#include <Eigen/Core>

namespace hymm::denseslam
{
/** What denseGaussiansInBox read. */
struct DenseGaussiansStats
{
    size_t regions = 0;             //!< regions meeting the box
    size_t regions_degenerate = 0;  //!< skipped: their current triangle is no frame
    size_t read = 0;                //!< Gaussians or points transformed
};

/** The Gaussians of the regions meeting the box [lo, hi] (global frame) whose current
 *  means lie in it: each region's SOG layer components, or, for a region without a SOG
 *  layer, its points layer's points with covariance point_std_m^2 I; all at the region's
 *  current affine map (thesis 3.4), so they move with the landmarks. Fallback tiles are
 *  not read: they are anchored to no landmark. The cost is that of the regions meeting
 *  the box (RegionPartition::regionsInBox), not of the map. */
scanslam::PointSet denseGaussiansInBox(const ltr::RegionPartition& partition, const dense::HybridMetricMap& map,
                                       const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double point_std_m,
                                       DenseGaussiansStats* stats = nullptr);

}  // namespace hymm::denseslam
