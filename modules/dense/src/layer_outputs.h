/**
 * @file layer_outputs.h
 * @brief The output hooks of each layer kind (LayerOutputs.h), one function per kind,
 *        defined beside the layer in `<Layer>Outputs.cpp`; the layer table
 *        (LayerRegistry.cpp) puts them in the kind's row.
 */
#pragma once

#include "hymm/dense/LayerOutputs.h"

namespace hymm::dense
{
LayerOutputs pointsLayerOutputs();
LayerOutputs occupancyLayerOutputs();
LayerOutputs particlesLayerOutputs();
LayerOutputs sogLayerOutputs();
LayerOutputs propertyLayerOutputs();

}  // namespace hymm::dense
