/**
 * @file PropertyLayer.h
 * @brief Scalar property grid of one region (thesis Sec. 3.4.1 / 4.5 multi-layer maps:
 *        any environment property, not only occupancy).
 *
 * Each return may carry a scalar (laser intensity, elevation, a value from another
 * sensor; RegionScan::hit_values) with a 1-sigma (hit_value_stds, or the configured
 * default). Values falling in the same cell (reference frame, `cell_size_m`) are fused
 * by inverse-variance weighting, the minimum-variance unbiased combination of
 * independent Gaussian measurements of one quantity:
 *   mean = sum(v_i / s_i^2) / sum(1 / s_i^2),   variance = 1 / sum(1 / s_i^2).
 * The cell stores the two sums (information form), so fusion is order independent and
 * exact. Cells are kept sparse (hash map): returns cover lines, not areas.
 *
 * Rendering: into an mrpt::maps::CHeightGridMap2D (h = mean, var = standard deviation
 * as its field documents, w = number of fused values), or into ScalarField mean / std
 * images (renderFields), which map_images.h writes as PNG colour maps.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include "hymm/dense/DenseLayer.h"
#include "hymm/dense/ScalarField.h"

#include <mrpt/config/CLoadableOptions.h>

#include <cstdint>
#include <optional>
#include <unordered_map>

namespace hymm::dense
{
class PropertyLayer : public DenseLayer
{
public:
    /** Ini section [PropertyLayer]; unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        double cell_size_m = 0.2;        //!< [m] local cell (reference frame)
        double default_value_std = 1.0;  //!< value units; used when a return has no std

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "PropertyLayer") const;
    };

    struct Estimate
    {
        double mean = 0;
        double variance = 0;
        std::uint32_t count = 0;  //!< values fused
    };

    static constexpr const char* kKind = "property";

    PropertyLayer(const Options& options, const hymm::ltr::TriangleFrame::Vertices& reference);

    std::string kind() const override { return kKind; }
    /** Fuses hit_values (ignored when empty); throws std::invalid_argument on sizes that
     *  do not match `hits`, non-finite values or stds that are not finite and > 0. */
    void insert(const RegionScan& scan) override;
    /** Cells holding at least one value. */
    size_t size() const override { return cells_.size(); }
    size_t memoryBytes() const override;
    /** Into a mrpt::maps::CHeightGridMap2D the caller sized: every cell whose centre lies
     *  in the current triangle and maps onto an observed local cell. */
    void renderInto(
        const hymm::ltr::AffineRegionMap& reference_to_current,
        mrpt::maps::CMetricMap& out) const override;
    void save(std::ostream& out) const override;
    void load(std::istream& in) override;
    void saveState(mrpt::serialization::CArchive& out) const override;  //!< DenseLayerState.cpp
    void loadState(mrpt::serialization::CArchive& in) override;

    /** Fuses one value at a reference-frame point (same checks as insert()). */
    void fuse(const Eigen::Vector2d& p_ref, double value, double value_std);
    /** Estimate of the cell holding `p_ref`, nullopt if never observed. */
    std::optional<Estimate> estimateAt(const Eigen::Vector2d& p_ref) const;
    /** Writes mean and standard deviation into the cells of `mean` (and `stddev`, same
     *  geometry, may be null) whose centre lies in the current triangle and reads an
     *  observed local cell. Other cells are left as they are. */
    void renderFields(
        const hymm::ltr::AffineRegionMap& reference_to_current, ScalarField& mean, ScalarField* stddev) const;

private:
    struct Cell
    {
        double info = 0;      // sum 1 / s^2
        double weighted = 0;  // sum v / s^2
        std::uint32_t count = 0;
    };
    std::int64_t keyOf(const Eigen::Vector2d& p_ref) const;
    const Cell* cellAt(const Eigen::Vector2d& p_ref) const;

    const Options options_;
    const hymm::ltr::TriangleFrame::Vertices reference_;
    std::unordered_map<std::int64_t, Cell> cells_;
};

}  // namespace hymm::dense
