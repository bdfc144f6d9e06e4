/**
 * @file SogLayer.h
 * @brief Sum-of-Gaussians shape of one region (thesis Sec. 4.3, SOG-DenseSLAM).
 *
 * Observation model (Eq. 4.15-4.16): each return becomes a Gaussian with mean at the
 * return and covariance P = J R J^T, J the Jacobian of (r cos t, r sin t) w.r.t.
 * (r, t) evaluated in the current (metric) frame, then mapped to the reference frame
 * with the linear part of current -> reference (P_ref = A^{-1} P A^{-T}).
 *
 * Update (Sec. 4.3.2, steps 1-4): every Gaussian of the map takes the nearest Gaussian
 * of the scan (nearest neighbour); if their means are closer than d_min the two are
 * fused into the map Gaussian and the scan Gaussian is consumed. Scan Gaussians that
 * fused with nothing are added. Prior Gaussians with no scan Gaussian within d_min
 * (including everything outside the sensor view) are untouched.
 * Revisits (`absorb_within_d_min`, default on): a scan Gaussian that no map Gaussian took
 * but that lies within d_min of one is fused into its nearest map Gaussian instead of
 * being added. In the thesis' step each map Gaussian takes ONE scan Gaussian, so where a
 * scan holds several returns within d_min of a component (consecutive beams on a near
 * wall) all but one become new components, also where the surface is already mapped:
 * the chapter-3 world gains ~3k components per lap, linearly, and every insert walks
 * them all (docs/benchmarks.md "Soak"). Absorbing them keeps the components at least
 * d_min apart at birth. Off: the thesis.
 * Revisits (`merge_within_m`, default 0 = off, the thesis; e.g. 0.1 m = d_min / 2): a map
 * Gaussian that fused a scan Gaussian moves (Eq. 4.17 halves its distance to the return),
 * and over many laps the fused means wander into each other while the noise tails keep
 * giving birth to components in the gaps (+1.4k components a lap after 20 laps of the
 * chapter-3 world with absorbing alone). A map Gaussian that moved in this insert and now
 * lies within merge_within_m of another map Gaussian is merged with it: the older of the
 * two (it has fused more returns) stays as it is, the younger goes. Every component a revisit touched is then at least that
 * far from the others, which bounds their number by the area mapped. Below d_min, so that
 * neighbouring beams' components on a near surface (0.17 m apart at 5 m for 2 deg beams)
 * stay apart; a first visit (empty map) is unchanged. Off by default: the fewer
 * components each take the returns of a wider area, and Eq. 4.17 moves a component
 * halfway to each, so they sit as far from the surface as the raw returns (a test: 0.080
 * instead of 0.041 m after 400 revisits of a wall, 34 instead of 292 components).
 * Revisits (`max_mean_per_cell`, default 3; 0 = unbounded, the thesis): after an insert
 * that added components, a region (or fallback tile) holding more than this many
 * components per square cell of side d_min that their means occupy merges its closest
 * pairs until it does not. Sec. 4.3.2 asks to "cover the areas where observations are
 * received with the smallest possible number of Gaussians" and Sec. 4.3.3 notes that the
 * SOG "could be subsampled and still maintain a representation of similar quality" but
 * leaves subsampling out. The bound follows the area the components cover, not the number
 * of visits: absorbing alone still adds ~1.4k components a lap after 20 laps of the
 * chapter-3 world, because neighbouring map Gaussians that take the same return move
 * halfway towards it (Eq. 4.17) and towards each other, and the tails give birth in the
 * gaps they leave. The merge keeps the mean and covariance of the surface the pair draws
 * (each Gaussian has peak 1, Fig. 4.11, so its weight is sqrt|P|): a merged Gaussian
 * covers what the two covered, where the "average of the means, sum of the variances"
 * suggested in Sec. 4.3.2 would double the width across the surface. The closest pairs
 * are the Gaussians that drifted together. 3 is above what a first visit leaves (2.2 per
 * cell for a wall at 5 m in the test), so a region's first visits are the thesis'; the
 * price is a little accuracy after many revisits (fewer Gaussians each fuse more returns
 * per scan: 0.054 instead of 0.041 m from the wall after 400 revisits, the returns
 * 0.078 m; SogLayerTest.RevisitsAreBoundedByTheAreaAndStayOnTheSurface).
 * Fusion rules:
 *  - "average" (the thesis): mean (x_priori + x_obs) / 2 (Eq. 4.17); covariance
 *    P_priori + P_obs if sigma_priori + sigma_obs <= k d_min (Eq. 4.18-4.19), else
 *    P_priori (Eq. 4.20).
 *  - "product": the Bayesian product of the two Gaussians (mrpt::poses::
 *    CPoint2DPDFGaussian::bayesianFusion), the fusion of ref. [49] that Sec. 4.3
 *    argues is inconsistent for surfaces; kept for comparison.
 * Eq. 4.18 as printed compares a sum of "variances" with the length k d_min, which is
 * dimensionally inconsistent; sigma is read as a standard deviation: the major
 * semi-axis of the 1-sigma ellipse, sqrt(lambda_max(P)).
 *
 * The map is not a distribution (Sec. 4.3); it is drawn as Gaussians of peak 1 (Fig.
 * 4.12 b) summed on a grid, or as 1-sigma ellipses (Fig. 4.13).
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include "hymm/dense/DenseLayer.h"
#include "hymm/dense/ScalarField.h"
#include "hymm/dense/sensor_models.h"

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPoint2DPDFGaussian.h>

#include <vector>

namespace hymm::dense
{
class SogLayer : public DenseLayer
{
public:
    enum class FusionRule
    {
        Average,  //!< Eq. 4.17-4.20 (thesis)
        Product   //!< Bayesian product (ref. [49]); not the thesis' choice
    };

    /** Ini section [SogLayer]; unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        double range_std_m = 0.1;      //!< [m] sensor noise when the scan carries none (Table 4.1)
        double bearing_std_deg = 1.0;  //!< [deg] idem
        double d_min_m = 0.2;          //!< [m] fusion distance of the means (Sec. 4.3.3)
        double k = 0.8;                //!< Eq. 4.18 factor (Sec. 4.3.3)
        FusionRule fusion_rule = FusionRule::Average;  //!< ini: "average" | "product"
        double cutoff_sigmas = 3.0;    //!< surface rendering ignores a Gaussian beyond this
        /** a scan Gaussian no map Gaussian took is fused into the nearest one within
         *  d_min instead of being added (revisits; false = the thesis) */
        bool absorb_within_d_min = true;
        /** [m] a map Gaussian moved by this insert's fusions that lies within this of
         *  another map Gaussian is merged with it (revisits; 0 = the thesis); <= d_min */
        double merge_within_m = 0;
        /** components per region (or fallback tile) at most this times the square cells
         *  of side d_min their means occupy: beyond, the closest pairs are merged into
         *  one Gaussian with their mean and covariance (revisits; 0 = unbounded, the thesis) */
        double max_mean_per_cell = 3;
        /** [m] returns farther than this from the sensor add no Gaussian (0 = every
         *  return the map is given, the thesis): far returns are the widest Gaussians
         *  and each stays a component of its own (docs/results.md, "Why the SOG layer
         *  misses 0.3 m") */
        double max_range_m = 0;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "SogLayer") const;
        RangeBearingNoise noise() const;
    };

    struct Gaussian
    {
        Eigen::Vector2d mean;  //!< reference frame [m]
        Eigen::Matrix2d cov;   //!< reference frame [m^2], symmetric PSD
    };

    static constexpr const char* kKind = "sog";

    explicit SogLayer(const Options& options);

    std::string kind() const override { return kKind; }
    void insert(const RegionScan& scan) override;
    size_t size() const override { return gaussians_.size(); }
    size_t memoryBytes() const override;
    /** Into a mrpt::maps::CPointsMap: the means. Into a mrpt::maps::COccupancyGridMap2D:
     *  the surface (sum of this region's peak-1 Gaussians, clamped to [0, 1]), written
     *  as max(cell, value) so regions drawn into one grid do not erase each other. */
    void renderInto(
        const hymm::ltr::AffineRegionMap& reference_to_current,
        mrpt::maps::CMetricMap& out) const override;
    void save(std::ostream& out) const override;
    void load(std::istream& in) override;
    void saveState(mrpt::serialization::CArchive& out) const override;  //!< DenseLayerState.cpp
    void loadState(mrpt::serialization::CArchive& in) override;

    const std::vector<Gaussian>& gaussians() const { return gaussians_; }
    /** Gaussian `i` at the current region position, as an MRPT PDF. */
    mrpt::poses::CPoint2DPDFGaussian gaussianAt(
        size_t i, const hymm::ltr::AffineRegionMap& reference_to_current) const;
    /** Adds the sum of this region's peak-1 Gaussians (current position) to every cell
     *  of `field` within cutoff_sigmas of a mean (Fig. 4.12 b). */
    void addSurface(const hymm::ltr::AffineRegionMap& reference_to_current, ScalarField& field) const;
    /** 1-sigma ellipses (current position), `points` vertices each (Fig. 4.13). */
    std::vector<std::vector<Eigen::Vector2d>> ellipses(
        const hymm::ltr::AffineRegionMap& reference_to_current, int points = 36) const;

    /** Gaussians of one scan piece (Eq. 4.15-4.16) in reference coordinates. */
    std::vector<Gaussian> observationGaussians(const RegionScan& scan) const;
    /** The configured fusion of a map Gaussian with a scan Gaussian. */
    Gaussian fuse(const Gaussian& priori, const Gaussian& obs) const;

private:
    /** merge_within_m: merges the prior Gaussians [0, prior) flagged in `moved` with
     *  their neighbours within d_min (the header: revisits). */
    void mergeMoved(size_t prior, const std::vector<char>& moved);
    /** max_mean_per_cell: merges the closest pairs until the region is within its bound
     *  (SogLayerCap.cpp; the header: revisits). */
    void capComponents();

    const Options options_;
    std::vector<Gaussian> gaussians_;
};

/** One Gaussian with the mean and covariance of the pair, each weighted by its mass in
 *  the drawn surface (peak 1: sqrt|P|); SogLayerCap.cpp. */
SogLayer::Gaussian mergeMoments(const SogLayer::Gaussian& a, const SogLayer::Gaussian& b);

/** sqrt of the largest eigenvalue: the "sigma" of Eq. 4.18 (major 1-sigma semi-axis). */
double majorSigma(const Eigen::Matrix2d& cov);

}  // namespace hymm::dense
