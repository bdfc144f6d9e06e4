/**
 * @file output_helpers.h
 * @brief Small pieces several of hymm-slam's output files share. What is per dense layer
 *        kind (files, counters, scored points, summary line) is declared with the kind
 *        (dense::LayerKind::outputs, dense/LayerOutputs.h).
 */
#pragma once

#include <hymm/app/slam_outputs.h>
#include <hymm/dense/LayerRegistry.h>

#include <hymm/eval/MetricsJson.h>

#include <map>
#include <string>
#include <vector>

namespace hymm::app
{
/** What the layer output hooks of `slam`'s run see (its map must exist). */
dense::LayerOutputContext layerOutputContext(const DenseSlam& slam);

/** The kinds of the layers the run has on, in the table's order (none without a map). */
std::vector<const dense::LayerKind*> enabledLayerKinds(const DenseSlam& slam);

/** A counter of a layer kind into metrics.json. */
void setCounter(eval::MetricsJson& j, const dense::LayerCounter& counter);

size_t valueOr0(const std::map<std::string, size_t>& m, const std::string& key);

/** Landmarks in the filter by the feature kinds their observations came from. */
struct LandmarksByFeature
{
    size_t reflector_only = 0, tree_only = 0, both = 0;
};
LandmarksByFeature landmarksByFeature(const DenseSlam& slam);

}  // namespace hymm::app
