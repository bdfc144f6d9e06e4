/**
 * @file OccupancyLayer.h
 * @brief Occupancy grid of one region (thesis Sec. 4.1, OG-DenseSLAM).
 *
 * The grid is a uniform log-odds grid in the region's reference frame covering the
 * bounding box of the reference triangle; only cells whose square meets the triangle
 * are ever updated (neighbouring regions own the rest), so each region describes
 * exactly its own area. Cells along a shared edge exist in both neighbours; rendering
 * reads whichever region contains the sample point.
 *
 * Inverse sensor model (range-bearing, simplified from Eq. 4.4): cells a beam crosses
 * before its return get P(C|r) = prob_hit's counterpart prob_miss, the cell holding
 * the return gets prob_hit, cells beyond the return are untouched. The update is the
 * corrected Eq. 4.7 (see LogOddsGrid.h), clamped to [prob_clamp_min, prob_clamp_max]
 * so that cells stay revisable.
 *
 * Per-region resolution (Sec. 4.1.3, Fig. 4.6): coarsen() re-samples an "almost
 * empty" region to `coarse_cell_size_m`. A region is almost empty when the fraction of
 * its cells (those meeting the triangle) with P(occupied) < coarsen_min_prob exceeds
 * coarsen_cells_percent (thesis: minProb = 0.2, cellsPercent = 0.99, 0.2 m -> 0.5 m).
 * Each coarse cell takes the largest log-odds of the fine cells whose centres it holds
 * when one of them is occupied (P > 0.5), so the few occupied cells the criterion allows
 * (e.g. around the landmarks at the corners) survive; otherwise the mean log-odds.
 * Later scans update the coarse grid; a region is never refined again.
 *
 * Why an own grid rather than mrpt::maps::COccupancyGridMap2D for storage: MRPT's
 * insertObservation() traces whole beams from a sensor pose with its own likelihood
 * model and cannot be restricted to a triangle, and its cells hold 8/16-bit quantised
 * log-odds, so configured increments and clamps would not be represented exactly.
 * COccupancyGridMap2D is used for the global rendering instead.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include "hymm/dense/DenseLayer.h"
#include "hymm/dense/LogOddsGrid.h"

#include <mrpt/config/CLoadableOptions.h>

namespace hymm::dense
{
class OccupancyLayer : public DenseLayer
{
public:
    /** Ini section [OccupancyLayer]; unknown keys are errors. Probabilities are
     *  P(occupied) in (0, 1). */
    struct Options : public mrpt::config::CLoadableOptions
    {
        double cell_size_m = 0.1;      //!< [m] local grid cell (per region; may differ later)
        double prob_hit = 0.7;         //!< inverse sensor model at the cell of a return
        double prob_miss = 0.4;        //!< inverse sensor model along the beam before it
        double prob_prior = 0.5;       //!< P(C_i) before any observation
        double prob_clamp_min = 0.03;  //!< lower clamp of the posterior
        double prob_clamp_max = 0.97;  //!< upper clamp of the posterior
        double coarse_cell_size_m = 0.0;     //!< [m] cell after coarsen(); 0 = never coarsen
        double coarsen_cells_percent = 0.99; //!< cellsPercent: fraction of free cells needed
        double coarsen_min_prob = 0.2;       //!< minProb: a cell is free below this P

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "OccupancyLayer") const;

        /** Log-odds increments of Eq. 4.7 (corrected): logit(P(C|r)) - logit(P(C)). */
        float hitIncrement() const;
        float missIncrement() const;
        float priorLogOdds() const;
        float clampMinLogOdds() const;
        float clampMaxLogOdds() const;
    };

    static constexpr const char* kKind = "occupancy";

    /** Grid over the bounding box of `reference`, cells outside it frozen. */
    OccupancyLayer(const Options& options, const hymm::ltr::TriangleFrame::Vertices& reference);

    std::string kind() const override { return kKind; }
    void insert(const RegionScan& scan) override;
    /** Cells that were ever updated. */
    size_t size() const override { return grid_.changedCells(); }
    size_t memoryBytes() const override;
    /** Into a mrpt::maps::COccupancyGridMap2D: every global cell whose centre lies in
     *  the current triangle takes the probability of the local cell under it. */
    void renderInto(
        const hymm::ltr::AffineRegionMap& reference_to_current,
        mrpt::maps::CMetricMap& out) const override;
    void save(std::ostream& out) const override;
    void load(std::istream& in) override;
    void saveState(mrpt::serialization::CArchive& out) const override;  //!< DenseLayerState.cpp
    void loadState(mrpt::serialization::CArchive& in) override;

    /** Fraction of the triangle's cells with P(occupied) < `min_prob` (Sec. 4.1.3). */
    double freeFraction(double min_prob) const;
    /** Re-samples the grid to coarse_cell_size_m if the region is almost empty (see
     *  above) and not coarse yet; returns true if it did. */
    bool coarsen();
    /** True once the grid is at the coarse cell size. */
    bool isCoarse() const;

    /** P(occupied) at a reference-frame point (the prior outside the grid). */
    double probabilityAt(const Eigen::Vector2d& p_ref) const;
    const LogOddsGrid& grid() const { return grid_; }
    /** How renderInto() writes a cell of the triangle into the output grid. */
    enum class RenderMode
    {
        Overwrite,     //!< every cell, the prior included (default)
        ObservedOnly,  //!< cells never observed (at the prior) leave the output as it is
        /** Observed cells only, and only where the output is still at 0.5 or holds a
         *  lower probability: overlapping layers drawn into one grid keep the most occupied
         *  value (HybridMetricMap's fallback tiles of different anchors overlap; a tile
         *  that only saw a beam graze a wall must not erase the wall another tile saw). */
        MaxObserved
    };
    void setRenderMode(RenderMode m) { render_mode_ = m; }
    RenderMode renderMode() const { return render_mode_; }
    const hymm::ltr::TriangleFrame::Vertices& reference() const { return reference_; }

private:
    void restrictToTriangle();

    const Options options_;
    const hymm::ltr::TriangleFrame::Vertices reference_;
    LogOddsGrid grid_;
    RenderMode render_mode_ = RenderMode::Overwrite;
};

}  // namespace hymm::dense
