/**
 * @file PointsLayer.h
 * @brief Raw laser returns of one region (thesis Sec. 3.9).
 *
 * Every return is stored in the region it falls in, in reference-frame coordinates,
 * inside an mrpt::maps::CSimplePointsMap: MRPT's points map works unchanged because
 * the reference frame is an ordinary metric frame (DESIGN.md). It stores floats,
 * which is ~1e-5 m resolution at 100 m from the origin, well below laser noise.
 *
 * Optional thinning: with voxel_size_m > 0 at most one point is kept per square
 * voxel of that size (the first one), which bounds memory when the vehicle stands still.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include "hymm/dense/DenseLayer.h"

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CSimplePointsMap.h>

#include <cstdint>
#include <unordered_set>

namespace hymm::dense
{
class PointsLayer : public DenseLayer
{
public:
    /** Ini section [PointsLayer]; unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        double voxel_size_m = 0.0;  //!< [m] keep one point per voxel; 0 = keep every return

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "PointsLayer") const;
    };

    static constexpr const char* kKind = "points";

    explicit PointsLayer(const Options& options);

    std::string kind() const override { return kKind; }
    void insert(const RegionScan& scan) override;
    /** Adds points given in reference coordinates (same thinning as insert()). */
    void insertPoints(const std::vector<Eigen::Vector2d>& points_ref);
    size_t size() const override { return points_.size(); }
    size_t memoryBytes() const override;
    void renderInto(
        const hymm::ltr::AffineRegionMap& reference_to_current,
        mrpt::maps::CMetricMap& out) const override;
    void save(std::ostream& out) const override;
    void load(std::istream& in) override;

    /** Stored points, reference-frame coordinates. */
    const mrpt::maps::CSimplePointsMap& points() const { return points_; }

private:
    bool acceptVoxel(const Eigen::Vector2d& p);

    const Options options_;
    mrpt::maps::CSimplePointsMap points_;
    std::unordered_set<std::int64_t> voxels_;
};

}  // namespace hymm::dense
