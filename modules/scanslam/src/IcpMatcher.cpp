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

hymm::core::OptionTable IcpMatcher::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("threshold_dist_m", threshold_dist_m, "m", above(0, 100),
           "initial correspondence distance (CICP thresholdDist)");
    t.real("threshold_ang_deg", threshold_ang, "deg", atLeast(0, 90),
           "its growth with range (CICP thresholdAng)", M_PI / 180);
    t.real("alfa", alfa, "", above(0, 1), "threshold shrink factor per convergence (CICP ALFA)");
    t.real("smallest_threshold_dist_m", smallest_threshold_dist_m, "m", above(0, 100),
           "stop shrinking here");
    t.integer("max_iterations", max_iterations, "", 1, 100000, "CICP maxIterations");
    t.real("covariance_std_points_m", covariance_std_points_m, "m", above(0, 100),
           "CICP covariance_varPoints = this squared");
    t.real("min_goodness", min_goodness, "", between(0, 1),
           "CICP goodness below this: `too_few_matches`");
    t.real("cov_inflation", cov_inflation, "", above(0, 1000), "covariance multiplier (measured, see above)");
    return t;
}

void IcpMatcher::Options::load(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    table().load(cfg, section);
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
