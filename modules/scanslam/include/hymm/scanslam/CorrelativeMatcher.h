/**
 * @file CorrelativeMatcher.h
 * @brief Correlative scan matching (Olson 2009, the occupancy-correlation family of
 *        thesis 5.3): the scan becomes a grid of per-point log-likelihoods,
 *        -min(d^2 / 2 sigma^2, gate^2 / 2) with d the distance to the nearest scan point;
 *        a template pose scores the sum over its points (bilinear lookup). A coarse
 *        exhaustive search over the window (on a grid smoothed to the coarse step) picks
 *        a cell; a fine exhaustive search around it gives the score surface whose
 *        normalised exp(score) moments are the estimate and its covariance (plus the
 *        fine step's quantisation variance step^2 / 12).
 */
#pragma once

#include <hymm/core/OptionTable.h>

#include "hymm/scanslam/ScanMatcher.h"

namespace hymm::scanslam
{
class CorrelativeMatcher : public ScanMatcher
{
public:
    struct Options
    {
        double sigma_m = 0.15;              //!< point likelihood std [m]
        double gate_sigma = 3.0;            //!< log-likelihood floor at this distance [sigma]
        double grid_resolution_m = 0.03;    //!< likelihood grid cell [m]
        double search_xy_m = 0.6;           //!< half window in x and y [m]
        double search_phi = 6 * M_PI / 180; //!< half window in angle [rad]
        double coarse_step_m = 0.1;         //!< coarse translation step [m]
        double fine_step_m = 0.01;          //!< fine translation step [m]
        double min_matched_fraction = 0.5;  //!< template points within gate of the scan
        double cov_inflation = 3.0;         //!< covariance multiplier (README: measured)

        /** Every ini key, declared once: loader and README table come from it. */
        hymm::core::OptionTable table();
        void load(const mrpt::config::CConfigFileBase& cfg, const std::string& section);
    };

    CorrelativeMatcher();
    explicit CorrelativeMatcher(const Options& options) : options_(options) {}

    AlignResult align(const PointSet& tpl, const PointSet& scan, const Vec3& z0) const override;
    std::string name() const override { return "correlative"; }

private:
    Options options_;
};

}  // namespace hymm::scanslam
