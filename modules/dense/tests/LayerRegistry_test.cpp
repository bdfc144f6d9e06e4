/**
 * @file LayerRegistry_test.cpp
 * @brief The table of layer kinds: each row builds a layer of its own kind, only when its
 *        switch is on, and owns its options section (load, save, check).
 */
#include "hymm/dense/LayerRegistry.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <set>
#include <string>

namespace
{
using namespace hymm::dense;

const hymm::ltr::TriangleFrame::Vertices kReference{{{0, 0}, {10, 0}, {0, 10}}};

TEST(LayerRegistryTest, EachKindBuildsItsOwnLayerOnlyWhenSwitchedOn)
{
    std::set<std::string> names, sections;
    for (const LayerKind& k : layerKinds())
    {
        EXPECT_TRUE(names.insert(k.name).second) << k.name;
        EXPECT_TRUE(sections.insert(k.section).second) << k.section;
        EXPECT_EQ(findLayerKind(k.name), &k);
        HybridMetricMap::Options o;
        for (const LayerKind& other : layerKinds()) o.*(other.enabled) = false;
        o.*(k.enabled) = true;
        const HybridMetricMap map(o);
        EXPECT_EQ(map.enabledKinds(), std::vector<std::string>{k.name});
        const auto layer = map.makeLayer(k.name, kReference);
        ASSERT_TRUE(layer) << k.name;
        EXPECT_EQ(layer->kind(), k.name);
        EXPECT_EQ(layer->size(), 0u);
        for (const LayerKind& other : layerKinds())
        {
            if (&other == &k) continue;
            EXPECT_FALSE(map.makeLayer(other.name, kReference)) << other.name;
        }
    }
    EXPECT_EQ(findLayerKind("voxels"), nullptr);
    EXPECT_EQ(layerKindNames(), "points, occupancy, particles, sog, property");
}

TEST(LayerRegistryTest, EachKindReadsAndChecksItsOwnSection)
{
    for (const LayerKind& k : layerKinds())
    {
        // A key no section knows is an error naming the kind's section.
        mrpt::config::CConfigFileMemory bad("[" + std::string(k.section) + "]\nno_such_key=1\n");
        HybridMetricMap::Options o;
        try
        {
            k.load(o, bad);
            ADD_FAILURE() << k.section << " accepted an unknown key";
        }
        catch (const std::exception& e)
        {
            EXPECT_NE(std::string(e.what()).find(k.section), std::string::npos) << e.what();
        }
        // What a kind saves, it loads back, and the defaults pass its check.
        mrpt::config::CConfigFileMemory saved;
        k.save(HybridMetricMap::Options(), saved);
        EXPECT_TRUE(saved.sectionExists(k.section)) << k.section;
        EXPECT_NO_THROW(k.load(o, saved)) << k.section;
        EXPECT_NO_THROW(k.validate(o)) << k.section;
    }
}

}  // namespace
