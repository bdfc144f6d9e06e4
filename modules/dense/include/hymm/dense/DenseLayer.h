/**
 * @file DenseLayer.h
 * @brief One kind of dense content of a region (thesis Sec. 3.4.1 multi-layer maps, 4.5).
 *
 * A layer stores its content in metric coordinates of its region's reference triangle
 * (the vertex positions when the region was created). Stored content never changes
 * when the feature map is corrected; only the reference -> current affine map does,
 * and rendering applies it (Sec. 3.6: local coordinates are invariant after fusion).
 *
 * Implementations (kind() in quotes):
 *  - PointsLayer "points": raw returns (Sec. 3.9) -> mrpt::maps::CPointsMap;
 *  - OccupancyLayer "occupancy": log-odds grid (Sec. 4.1), per-region resolution by
 *    coarsen() (Sec. 4.1.3) -> mrpt::maps::COccupancyGridMap2D;
 *  - ParticlesLayer "particles": weighted samples (Sec. 4.2) -> CPointsMap
 *    (CPointsMapXYZI: weight as intensity);
 *  - SogLayer "sog": sum of Gaussians (Sec. 4.3) -> CPointsMap (means) or
 *    COccupancyGridMap2D (surface); exact surface / ellipses via SogLayer methods;
 *  - PropertyLayer "property": per-cell scalar mean / variance -> CHeightGridMap2D.
 * Each layer is constructed per region, so resolutions can differ between neighbours.
 */
#pragma once

#include "hymm/dense/RegionScan.h"
#include "hymm/ltr/AffineRegionMap.h"
#include "hymm/ltr/TriangleFrame.h"

#include <mrpt/maps/CMetricMap.h>

#include <iosfwd>
#include <memory>
#include <string>

namespace mrpt::serialization
{
class CArchive;
}

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
    /** Saved run state (hymm-slam --save-state): the content and everything the next
     *  insert reads (counters, random streams), bit for bit; loadState() replaces it.
     *  The default throws std::logic_error naming the kind (a layer that cannot be
     *  saved). Source: DenseLayerState.cpp. */
    virtual void saveState(mrpt::serialization::CArchive& out) const;
    virtual void loadState(mrpt::serialization::CArchive& in);
};

}  // namespace hymm::dense
