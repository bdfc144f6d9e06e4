/**
 * @file ScanMatcher.cpp
 * @brief Matcher factory and the covariance check the matchers share.
 */
#include "hymm/scanslam/ScanMatcher.h"

#include <Eigen/Eigenvalues>
#include <stdexcept>

#include "hymm/scanslam/CorrelativeMatcher.h"
#include "hymm/scanslam/IcpMatcher.h"
#include "hymm/scanslam/SogMatcher.h"

namespace hymm::scanslam
{
bool isCovariance(const Mat3& c, double min_eig)
{
    if (!c.allFinite() || (c - c.transpose()).cwiseAbs().maxCoeff() > 1e-9 * (1 + c.cwiseAbs().maxCoeff()))
        return false;
    Eigen::SelfAdjointEigenSolver<Mat3> es(c);
    return es.eigenvalues().minCoeff() > min_eig;
}

std::optional<AlignResult> rejectInput(const PointSet& tpl, const PointSet& scan, const Vec3& z0)
{
    AlignResult res;
    res.z = z0;
    if (tpl.size() < 3 || scan.size() < 3)
        res.failure = "too_few_points";
    else if (!z0.allFinite())
        res.failure = "bad_initial_guess";
    else
        return std::nullopt;
    return res;
}

AlignResult& finishAlignment(AlignResult& res, const Mat3& cov, double inflation)
{
    const Mat3 c = 0.5 * (cov + cov.transpose()) * inflation;
    if (!res.z.allFinite() || !isCovariance(c))
    {
        res.failure = "covariance_not_positive";
        return res;
    }
    res.R = c;
    res.ok = true;
    return res;
}

std::unique_ptr<ScanMatcher> makeMatcher(const std::string& kind,
                                         const mrpt::config::CConfigFileBase* cfg,
                                         const std::string& section)
{
    if (kind == "sog")
    {
        SogMatcher::Options o;
        if (cfg) o.load(*cfg, section);
        return std::make_unique<SogMatcher>(o);
    }
    if (kind == "icp")
    {
        IcpMatcher::Options o;
        if (cfg) o.load(*cfg, section);
        return std::make_unique<IcpMatcher>(o);
    }
    if (kind == "correlative")
    {
        CorrelativeMatcher::Options o;
        if (cfg) o.load(*cfg, section);
        return std::make_unique<CorrelativeMatcher>(o);
    }
    throw std::invalid_argument("unknown scan matcher '" + kind +
                                "' (expected sog, icp or correlative)");
}

}  // namespace hymm::scanslam
