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
 *
 * Bound by area (max_points_per_cell > 0): max_points is one number for every region, so
 * a region that sees a short wall fills up to it over the laps as one that sees a long
 * one does (in the 80-lap soak the total still grew by 2.4 k points a lap at lap 80, the
 * less visited regions and tiles filling towards 3,000 each). The sample is therefore also
 * held to max_points_per_cell times the number of square cells of side area_cell_m that
 * its own points occupy. The count is of the sample, not of every return: a fixed-size
 * uniform sample does not reach further into the noise tails however many laps are
 * driven, so the bound follows the area of the surfaces, and the sample settles where it
 * holds that many points per occupied cell on average. The count is redone after as many
 * returns were offered as the sample holds (amortised O(log n) per return, no index kept
 * beside the points); when it falls, points chosen uniformly leave the sample, and when it
 * rises, new returns join at the sample's current rate (limit / offered), so the sample
 * stays uniform over the returns to within the slack of a growing area.
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
         *  (reservoir sampling); 0 = no cap by count (with max_points_per_cell = 0 too:
         *  every return, thesis Sec. 3.9) */
        int max_points = 3000;
        int random_seed = 1;  //!< mixed with the region's vertices (reservoir sampling)
        /** the sample is also held to this many points per occupied cell of side
         *  area_cell_m (a bound by area, see above); 0 = max_points alone */
        double max_points_per_cell = 8.0;
        double area_cell_m = 0.2;  //!< [m] cell of the bound by area

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
    /** Points the sample may hold now: the smaller of max_points and the bound by area
     *  as last counted (0 = unbounded). */
    size_t limit() const;

private:
    bool acceptVoxel(const Eigen::Vector2d& p);
    /** Recounts the cells the sample occupies and drops uniformly chosen points beyond
     *  the new bound (max_points_per_cell). */
    void updateAreaLimit();

    const Options options_;
    mrpt::maps::CSimplePointsMap points_;
    std::unordered_set<std::int64_t> voxels_;
    size_t offered_ = 0;
    size_t area_limit_ = 0;        //!< max_points_per_cell x occupied cells, as last counted
    size_t next_area_check_ = 0;   //!< offered() at which the cells are counted again
    std::uint64_t rng_ = 0;  //!< splitmix64 state (8 bytes a region, not mt19937's 2.5 KB)
};

}  // namespace hymm::dense
