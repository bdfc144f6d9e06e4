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
 *
 * Revisits (max_points > 0): a region keeps at most max_points returns. Once full, the
 * n-th return offered (after the voxel thinning) replaces a stored one, chosen uniformly,
 * with probability max_points / n (reservoir sampling, Vitter's algorithm R), so the
 * stored points are always a uniform sample of every return the region received: the
 * spread of the points about the surfaces (the error statistics of the layer) stays that
 * of the raw returns however many laps are driven, while memory and the cost of anything
 * that reads the layer stop growing. (Thinning per voxel would bound memory too, but
 * keeps one point per voxel however rarely the voxel is hit: over many revisits the
 * noise tails fill and the cloud about a surface widens.) The random stream is seeded
 * from the region's reference vertices, so the same data give the same map. A layer
 * read by load() continues as if its points were all the returns it had seen.
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
        /** returns kept per region at most, a uniform sample of all it received
         *  (reservoir sampling); 0 = keep every return (thesis Sec. 3.9) */
        int max_points = 3000;
        int random_seed = 1;  //!< mixed with the region's vertices (reservoir sampling)

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "PointsLayer") const;
    };

    static constexpr const char* kKind = "points";

    /** `reference` (the region's vertices) seeds the reservoir sampling's stream. */
    PointsLayer(const Options& options, const hymm::ltr::TriangleFrame::Vertices& reference);
    /** As above, seeded from the option alone (all-zero vertices). */
    explicit PointsLayer(const Options& options);

    std::string kind() const override { return kKind; }
    void insert(const RegionScan& scan) override;
    /** Adds points given in reference coordinates (same thinning and cap as insert()). */
    void insertPoints(const std::vector<Eigen::Vector2d>& points_ref);
    size_t size() const override { return points_.size(); }
    size_t memoryBytes() const override;
    void renderInto(
        const hymm::ltr::AffineRegionMap& reference_to_current,
        mrpt::maps::CMetricMap& out) const override;
    void save(std::ostream& out) const override;
    void load(std::istream& in) override;
    void saveState(mrpt::serialization::CArchive& out) const override;  //!< DenseLayerState.cpp
    void loadState(mrpt::serialization::CArchive& in) override;

    /** Stored points, reference-frame coordinates. */
    const mrpt::maps::CSimplePointsMap& points() const { return points_; }
    /** Returns offered to the layer after the voxel thinning (stored or sampled away). */
    size_t offered() const { return offered_; }

private:
    bool acceptVoxel(const Eigen::Vector2d& p);

    const Options options_;
    mrpt::maps::CSimplePointsMap points_;
    std::unordered_set<std::int64_t> voxels_;
    size_t offered_ = 0;
    std::uint64_t rng_ = 0;  //!< splitmix64 state (8 bytes a region, not mt19937's 2.5 KB)
};

}  // namespace hymm::dense
