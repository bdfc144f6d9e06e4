/**
 * @file dense_gaussians.cpp
 * @brief denseGaussiansInBox: the SOG (or points) layers of the regions around a place,
 *        at their current affine maps.
 */
#include "hymm/denseslam/dense_gaussians.h"

#include <hymm/dense/PointsLayer.h>
#include <hymm/dense/SogLayer.h>

#include <optional>
#include <stdexcept>

namespace hymm::denseslam
{
scanslam::PointSet denseGaussiansInBox(const ltr::RegionPartition& partition, const dense::HybridMetricMap& map,
                                       const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double point_std_m,
                                       DenseGaussiansStats* stats)
{
    scanslam::PointSet out;
    DenseGaussiansStats st;
    if (!lo.allFinite() || !hi.allFinite() || (hi - lo).minCoeff() < 0) return out;
    const auto inside = [&](const Eigen::Vector2d& p) {
        return p.x() >= lo.x() && p.x() <= hi.x() && p.y() >= lo.y() && p.y() <= hi.y();
    };
    const Eigen::Matrix2d point_cov = point_std_m * point_std_m * Eigen::Matrix2d::Identity();
    for (long id : partition.regionsInBox(lo, hi))
    {
        ++st.regions;
        const dense::LocalDenseMap* lm = map.localMap(id);
        if (!lm) continue;
        const auto* sog = lm->layerAs<dense::SogLayer>(dense::SogLayer::kKind);
        const auto* pts = sog ? nullptr : lm->layerAs<dense::PointsLayer>(dense::PointsLayer::kKind);
        if (!sog && !pts) continue;
        std::optional<ltr::AffineRegionMap> a;
        try
        {
            a.emplace(partition.referenceToCurrent(id));
        }
        catch (const std::invalid_argument&)
        {
            ++st.regions_degenerate;
            continue;
        }
        if (sog)
            for (size_t i = 0; i < sog->size(); ++i)
            {
                const auto g = sog->gaussianAt(i, *a);
                const Eigen::Vector2d m(g.mean.x(), g.mean.y());
                ++st.read;
                if (inside(m)) out.add(m, g.cov.asEigen());
            }
        else
        {
            const auto& xs = pts->points().getPointsBufferRef_x();
            const auto& ys = pts->points().getPointsBufferRef_y();
            // A point's reference-frame noise is the sensor's, mapped like a direction.
            const Eigen::Matrix2d cov = a->linear() * point_cov * a->linear().transpose();
            for (size_t i = 0; i < xs.size(); ++i)
            {
                const Eigen::Vector2d m = a->mapPoint({xs[i], ys[i]});
                ++st.read;
                if (inside(m)) out.add(m, cov);
            }
        }
    }
    if (stats) *stats = st;
    return out;
}

}  // namespace hymm::denseslam
