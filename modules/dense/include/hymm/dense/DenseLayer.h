/**
 * @file DenseLayer.h
 * @brief One kind of dense content of a region (thesis Sec. 3.4.1 multi-layer maps, 4.5).
 *
 * A layer stores its content in metric coordinates of its region's reference triangle
 * (the vertex positions when the region was created). Stored content never changes
 * when the feature map is corrected; only the reference -> current affine map does,
 * and rendering applies it (Sec. 3.6: local coordinates are invariant after fusion).
 *
 * Implementations now: PointsLayer (Sec. 3.9 raw returns) and OccupancyLayer (Sec. 4.1).
 * The interface is meant to take further kinds without change: particle sets and sums
 * of Gaussians (render to points / sampled grids), scalar property grids (render by
 * sampling like OccupancyLayer), and per-region resolution (each layer is constructed
 * per region, so its cell size can differ from its neighbours').
 */
#pragma once

#include "hymm/dense/RegionScan.h"
#include "hymm/ltr/AffineRegionMap.h"
#include "hymm/ltr/TriangleFrame.h"

#include <mrpt/maps/CMetricMap.h>

#include <iosfwd>
#include <memory>
#include <string>

namespace hymm::dense
{
class DenseLayer
{
public:
    virtual ~DenseLayer() = default;
    DenseLayer() = default;
    DenseLayer(const DenseLayer&) = delete;
    DenseLayer& operator=(const DenseLayer&) = delete;

    /** Stable type name, used as the layer key and in files ("points", "occupancy"). */
    virtual std::string kind() const = 0;

    /** Fuses one scan piece given in reference-frame coordinates. */
    virtual void insert(const RegionScan& scan) = 0;

    /** Number of stored elements (points, cells that were ever updated, ...). */
    virtual size_t size() const = 0;
    /** Approximate heap + object memory [bytes]. */
    virtual size_t memoryBytes() const = 0;

    /** Draws the content at the CURRENT position of the region into `out`, mapping
     *  reference coordinates through `reference_to_current`. Each kind supports the
     *  MRPT map types it can be drawn into (points: mrpt::maps::CPointsMap; occupancy:
     *  mrpt::maps::COccupancyGridMap2D) and throws std::invalid_argument otherwise. */
    virtual void renderInto(
        const hymm::ltr::AffineRegionMap& reference_to_current,
        mrpt::maps::CMetricMap& out) const = 0;

    /** Text serialisation of the content (the kind is written by the owner). */
    virtual void save(std::ostream& out) const = 0;
    /** Replaces the content; throws std::runtime_error on malformed input. */
    virtual void load(std::istream& in) = 0;
};

}  // namespace hymm::dense
