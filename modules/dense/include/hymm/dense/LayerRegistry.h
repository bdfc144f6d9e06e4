/**
 * @file LayerRegistry.h
 * @brief Every dense layer kind, declared once (thesis Sec. 3.4.1: a region holds one
 *        layer per kind of dense information).
 *
 * A kind is one row of layerKinds(): its name (DenseLayer::kind(), the item of
 * `[DenseSlam] dense_layers`, the stem of its output files), the ini section of its
 * options, its `enable_*` switch and options in HybridMetricMap::Options, and its
 * factory. HybridMetricMap (layer
 * construction for regions, fallback tiles and saved states, options loading, saving and
 * checking), DenseSlam (`dense_layers`) and the application's outputs iterate over it.
 * Each layer draws itself (DenseLayer::renderInto, through HybridMetricMap::renderLayer).
 *
 * Adding a kind: the layer's files (class, options with their section) and one row here
 * (LayerRegistry.cpp); the application adds its files and metrics in the table of
 * app/src/layer_outputs.cpp, which a test keeps in step with this one (the app module is
 * above `dense`: metrics.json and the run counters are not known here).
 */
#pragma once

#include "hymm/dense/HybridMetricMap.h"

#include <memory>
#include <string>
#include <vector>

namespace hymm::dense
{
struct LayerKind
{
    const char* name;     //!< DenseLayer::kind() of its layers
    const char* section;  //!< ini section of its options
    const char* doc;      //!< what its layers keep (the `enable_<name>` key's description)
    /** Its switch in HybridMetricMap::Options (`enable_<name>`). */
    bool HybridMetricMap::Options::*enabled;
    /** A new empty layer for a region whose reference triangle is `reference`. */
    std::unique_ptr<DenseLayer> (*make)(
        const HybridMetricMap::Options& options, const hymm::ltr::TriangleFrame::Vertices& reference);
    /** Reads / writes / checks its options (in `options`) under `section`. */
    void (*load)(HybridMetricMap::Options& options, const mrpt::config::CConfigFileBase& cfg);
    void (*save)(const HybridMetricMap::Options& options, mrpt::config::CConfigFileBase& cfg);
    void (*validate)(const HybridMetricMap::Options& options);
};

/** Every kind, in the order regions hold them and outputs list them. */
const std::vector<LayerKind>& layerKinds();

/** The kind named `name`; nullptr if there is none. */
const LayerKind* findLayerKind(const std::string& name);

/** "points, occupancy, ..." (for error messages). */
std::string layerKindNames();

}  // namespace hymm::dense
