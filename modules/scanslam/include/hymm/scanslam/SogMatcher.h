/**
 * @file SogMatcher.h
 * @brief The thesis' scan alignment (5.3.1, 5.4): the likelihood of a relative pose is
 *        the cross-correlation of the template's and the scan's sums of Gaussians
 *        (Eq. 5.13), maximised by damped Newton steps over a coarse-to-fine series of
 *        smoothing scales; its covariance is fitted to the likelihood's values around
 *        the maximum (Eqs. 5.16-5.17, least squares by SVD).
 *
 * Smoothing adds s^2 I to every pair's covariance (the scaled SOG of the thesis'
 * reference [1]) so that coarse levels widen the basin of convergence; the last level
 * is normally s = 0, the likelihood of Eq. 5.13 itself, from which the covariance comes.
 */
#pragma once

#include <hymm/core/OptionTable.h>

#include <limits>
#include <vector>

#include "hymm/scanslam/ScanMatcher.h"

namespace hymm::scanslam
{
class SogMatcher : public ScanMatcher
{
public:
    /** sum: ln of Lambda of Eq. 5.13, all pairs summed (the thesis' literal form; its
     *  curvature is that of an average single point, so the covariance of 5.4 on it
     *  is about N times too large, see the README). product: sum over template points
     *  of ln(sum over scan points), the likelihood of independent template points
     *  (each a mixture over the scan), whose curvature carries all N points. */
    enum class Objective
    {
        product,
        sum
    };

    struct Options
    {
        Objective objective = Objective::product;  //!< ini: objective = product | sum
        std::vector<double> scales_m{0.5, 0.2, 0.0};  //!< smoothing std per level [m]
        int max_iterations = 40;         //!< Newton steps per level
        double gate_sigma = 4.0;         //!< pairs further apart are left out [sigma]
        double min_matched_fraction = 0.5;  //!< template points within 3 sigma of the scan
        double max_correction_m = 1.0;   //!< result further from z0 than this: diverged [m]
        double max_correction = 15 * M_PI / 180;  //!< same for the angle [rad] (ini: _deg)
        double cov_inflation = 1.0;      //!< covariance multiplier (README: measured)

        /** Every ini key, declared once: loader and README table come from it. */
        hymm::core::OptionTable table();
        void load(const mrpt::config::CConfigFileBase& cfg, const std::string& section);
    };

    /** The objective (see Objective) and its derivatives with respect to z = (x, y, phi). */
    struct Evaluation
    {
        double log_l = -std::numeric_limits<double>::infinity();
        Vec3 gradient = Vec3::Zero();
        Mat3 hessian = Mat3::Zero();
        size_t matched = 0;  //!< template points with a pair within 3 sigma
    };

    SogMatcher();
    explicit SogMatcher(const Options& options) : options_(options) {}

    AlignResult align(const PointSet& tpl, const PointSet& scan, const Vec3& z0) const override;
    std::string name() const override { return "sog"; }

    /** ln Lambda(z) of Eq. 5.13 with the smoothing variance `extra_var` added to every
     *  pair. The pair covariances R(cov_phi) P_i R(cov_phi)^T + Q_j take the rotation
     *  `cov_phi`; the derivatives treat them as constant (exact when cov_phi is held
     *  fixed; the optimiser sets cov_phi = z.phi, so compared values are exact). */
    Evaluation evaluate(const PointSet& tpl, const PointSet& scan, const Vec3& z,
                        double extra_var, double cov_phi, bool derivatives) const;

    const Options& options() const { return options_; }

private:
    Options options_;
};

}  // namespace hymm::scanslam
