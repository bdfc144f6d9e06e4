/**
 * @file LayerRegistry.h
 * @brief Every dense layer kind, declared once (thesis Sec. 3.4.1: a region holds one
 *        layer per kind of dense information).
 *
 * A kind is one row of layerKinds(): its name (DenseLayer::kind(), the item of
 * `[DenseSlam] dense_layers`, the stem of its output files), the ini section of its
 * options, its `enable_*` switch and options in HybridMetricMap::Options, its factory
 * and its output hooks (files, metrics.json counters, the points its outline metrics
 * score, its summary line: LayerOutputs.h). HybridMetricMap (layer construction for
 * regions, fallback tiles and saved states, options loading, saving and checking),
 * DenseSlam (`dense_layers`) and hymm-slam's outputs, metrics and summary iterate over
 * it. Each layer draws itself (DenseLayer::renderInto, through
 * HybridMetricMap::renderLayer, which is also what the MRPT map wrapper and the 3D scene
 * show).
 *
 * Adding a kind touches this module only: the layer's files (class, options with their
 * section, `src/<Layer>Outputs.cpp` with its hooks), its options member and switch in
 * HybridMetricMap::Options (typed, so that code configuring a layer is checked by the
 * compiler) and one row in LayerRegistry.cpp (modules/dense/README.md, "Adding a layer
 * kind"); hymm-options-doc takes its key table from the row too.
 */
#pragma once

#include "hymm/dense/HybridMetricMap.h"
#include "hymm/dense/LayerOutputs.h"

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
    /** Its options' declarations (in `options`), for the key table of modules/dense/README.md. */
    core::OptionTable (*table)(HybridMetricMap::Options& options);
    /** What a run writes, counts, scores and summarises of the kind. */
    LayerOutputs outputs;
};

/** Every kind, in the order regions hold them and outputs list them. */
const std::vector<LayerKind>& layerKinds();

/** The kind named `name`; nullptr if there is none. */
const LayerKind* findLayerKind(const std::string& name);

/** "points, occupancy, ..." (for error messages). */
std::string layerKindNames();

}  // namespace hymm::dense
