/**
 * @file IcpMatcher.cpp
 * @brief mrpt::slam::CICP behind the ScanMatcher interface.
 */
#include "hymm/scanslam/IcpMatcher.h"

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include "hymm/core/config_utils.h"

namespace hymm::scanslam
{
IcpMatcher::IcpMatcher() : options_() {}

void IcpMatcher::Options::load(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    using namespace hymm::core;
    checkKnownKeys(cfg, section,
                   {"threshold_dist_m", "threshold_ang_deg", "alfa", "smallest_threshold_dist_m",
                    "max_iterations", "covariance_std_points_m", "min_goodness",
                    "cov_inflation"});
    threshold_dist_m = readDoubleMin(cfg, section, "threshold_dist_m", threshold_dist_m, 0, true);
    threshold_ang = M_PI / 180 * readDoubleMin(cfg, section, "threshold_ang_deg",
                                               threshold_ang * 180 / M_PI, 0, false);
    alfa = readDoubleMin(cfg, section, "alfa", alfa, 0, true);
    smallest_threshold_dist_m = readDoubleMin(cfg, section, "smallest_threshold_dist_m",
                                              smallest_threshold_dist_m, 0, true);
    max_iterations = static_cast<int>(readInt(cfg, section, "max_iterations", max_iterations));
    if (max_iterations < 1)
        throwConfigError(section, "max_iterations", std::to_string(max_iterations), "must be >= 1");
    covariance_std_points_m =
        readDoubleMin(cfg, section, "covariance_std_points_m", covariance_std_points_m, 0, true);
    min_goodness = readDoubleMin(cfg, section, "min_goodness", min_goodness, 0, false);
    cov_inflation = readDoubleMin(cfg, section, "cov_inflation", cov_inflation, 0, true);
}

AlignResult IcpMatcher::align(const PointSet& tpl, const PointSet& scan, const Vec3& z0) const
{
    if (auto bad = rejectInput(tpl, scan, z0)) return *bad;
    AlignResult res;
    res.z = z0;
    mrpt::maps::CSimplePointsMap ref, moving;
    ref.reserve(scan.size());
    for (const Vec2& q : scan.points) ref.insertPoint(static_cast<float>(q.x()), static_cast<float>(q.y()), 0.f);
    moving.reserve(tpl.size());
    for (const Vec2& p : tpl.points) moving.insertPoint(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.f);

    mrpt::slam::CICP icp;
    icp.options.ICP_algorithm = mrpt::slam::icpClassic;
    icp.options.thresholdDist = options_.threshold_dist_m;
    icp.options.thresholdAng = options_.threshold_ang;
    icp.options.ALFA = options_.alfa;
    icp.options.smallestThresholdDist = options_.smallest_threshold_dist_m;
    icp.options.maxIterations = static_cast<unsigned>(options_.max_iterations);
    icp.options.covariance_varPoints = options_.covariance_std_points_m * options_.covariance_std_points_m;
    icp.options.corresponding_points_decimation = 1;
    icp.options.onlyUniqueRobust = false;

    mrpt::slam::CICP::TReturnInfo info;
    // CICP estimates the pose of m2 (the template) relative to m1 (the scan).
    const auto pdf = icp.Align(&ref, &moving, mrpt::poses::CPose2D(z0.x(), z0.y(), z0.z()), info);
    const auto* g = dynamic_cast<const mrpt::poses::CPosePDFGaussian*>(pdf.get());
    if (!g)
    {
        res.failure = "no_gaussian";
        return res;
    }
    res.iterations = static_cast<int>(info.nIterations);
    res.score = info.goodness;
    res.z = Vec3(g->mean.x(), g->mean.y(), g->mean.phi());
    if (info.goodness < options_.min_goodness)
    {
        res.failure = "too_few_matches";
        return res;
    }
    Mat3 cov;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) cov(r, c) = g->cov(r, c);
    return finishAlignment(res, cov, options_.cov_inflation);
}

}  // namespace hymm::scanslam
