/**
 * @file IcpMatcher.h
 * @brief Scan alignment by MRPT's ICP (mrpt::slam::CICP, classic point-to-point with
 *        shrinking correspondence thresholds), with the covariance CICP reports
 *        (finite differences of its matching error, scaled by covariance_varPoints),
 *        multiplied by the measured cov_inflation.
 */
#pragma once

#include <hymm/core/OptionTable.h>

#include <mrpt/slam/CICP.h>

#include "hymm/scanslam/ScanMatcher.h"

namespace hymm::scanslam
{
class IcpMatcher : public ScanMatcher
{
public:
    struct Options
    {
        double threshold_dist_m = 1.0;       //!< initial correspondence distance [m]
        double threshold_ang = 0.15 * M_PI / 180;  //!< its growth with range [rad]
        double alfa = 0.5;                   //!< threshold shrink factor per convergence
        double smallest_threshold_dist_m = 0.2;  //!< stop shrinking here [m]
        int max_iterations = 80;
        double covariance_std_points_m = 0.1;  //!< CICP covariance_varPoints = this^2 [m]
        double min_goodness = 0.5;  //!< fraction of template points with a correspondence
        double cov_inflation = 2.7;  //!< covariance multiplier (README: measured)

        /** Every ini key, declared once: loader and README table come from it. */
        hymm::core::OptionTable table();
        void load(const mrpt::config::CConfigFileBase& cfg, const std::string& section);
    };

    IcpMatcher();
    explicit IcpMatcher(const Options& options) : options_(options) {}

    AlignResult align(const PointSet& tpl, const PointSet& scan, const Vec3& z0) const override;
    std::string name() const override { return "icp"; }

private:
    Options options_;
};

}  // namespace hymm::scanslam
