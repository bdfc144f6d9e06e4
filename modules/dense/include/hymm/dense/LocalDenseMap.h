/**
 * @file LocalDenseMap.h
 * @brief All dense layers of one region (thesis Sec. 3.4.1 multi-layer maps, 4.5).
 *
 * One LocalDenseMap per LTR. It holds any set of layers, at most one of each kind, all
 * in the reference-frame coordinates of the region's reference triangle; insert()
 * fuses the same scan piece into every layer, so e.g. the raw points and the
 * occupancy grid of a region always come from the same observations.
 */
#pragma once

#include "hymm/dense/DenseLayer.h"

#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace mrpt::serialization
{
class CArchive;
}

namespace hymm::dense
{
class LocalDenseMap
{
public:
    /** Builds an empty layer of `kind` for a region with `reference` vertices. */
    using LayerFactory = std::function<std::unique_ptr<DenseLayer>(
        const std::string& kind, const hymm::ltr::TriangleFrame::Vertices& reference)>;

    LocalDenseMap(long region_id, const hymm::ltr::TriangleFrame::Vertices& reference);
    LocalDenseMap(const LocalDenseMap&) = delete;
    LocalDenseMap& operator=(const LocalDenseMap&) = delete;

    long regionId() const { return region_id_; }
    const hymm::ltr::TriangleFrame::Vertices& reference() const { return reference_; }

    /** Throws std::invalid_argument if a layer of the same kind exists. */
    void addLayer(std::unique_ptr<DenseLayer> layer);
    /** nullptr if there is no layer of that kind. */
    const DenseLayer* layer(const std::string& kind) const;
    DenseLayer* layer(const std::string& kind);
    /** The layer of `kind` as its concrete type, or nullptr. */
    template <class T>
    const T* layerAs(const std::string& kind) const
    {
        return dynamic_cast<const T*>(layer(kind));
    }
    std::vector<std::string> layerKinds() const;

    /** Fuses `scan` (reference coordinates) into every layer. */
    void insert(const RegionScan& scan);

    size_t memoryBytes() const;

    /** Text form: region id, reference vertices, then each layer with its kind. */
    void save(std::ostream& out) const;
    /** Throws std::runtime_error on malformed input or an unknown kind. */
    static std::unique_ptr<LocalDenseMap> load(std::istream& in, const LayerFactory& factory);
    /** Saved run state of the region map and its layers (DenseLayer::saveState);
     *  source: HybridMetricMapState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    static std::unique_ptr<LocalDenseMap> loadState(mrpt::serialization::CArchive& in,
                                                    const LayerFactory& factory);

private:
    const long region_id_;
    const hymm::ltr::TriangleFrame::Vertices reference_;
    std::vector<std::unique_ptr<DenseLayer>> layers_;
};

}  // namespace hymm::dense
