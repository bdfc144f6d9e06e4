// hymm-slam's outputs per dense layer kind: one entry for each kind of the dense layer
// table (dense::layerKinds), in its order, with every hook the outputs call.
#include "layer_outputs.h"

#include <gtest/gtest.h>
#include <hymm/dense/LayerRegistry.h>

namespace
{
TEST(LayerOutputsTest, OneEntryPerRegisteredLayerKindInTheSameOrder)
{
    const auto& kinds = hymm::dense::layerKinds();
    const auto& outputs = hymm::app::layerOutputs();
    ASSERT_EQ(outputs.size(), kinds.size());
    for (size_t i = 0; i < kinds.size(); ++i)
    {
        EXPECT_EQ(outputs[i].kind, kinds[i].name);
        EXPECT_EQ(hymm::app::findLayerOutput(kinds[i].name), &outputs[i]);
        EXPECT_TRUE(outputs[i].write && outputs[i].scored_points && outputs[i].describe) << outputs[i].kind;
    }
    EXPECT_EQ(hymm::app::findLayerOutput("voxels"), nullptr);
}
}  // namespace
