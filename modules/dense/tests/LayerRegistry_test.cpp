/**
 * @file LayerRegistry_test.cpp
 * @brief The table of layer kinds: each row builds a layer of its own kind, only when its
 *        switch is on, owns its options section (load, save, check) and its outputs
 *        (files MRPT reads back, counters, the points its outline metrics score, a
 *        summary line).
 */
#include "hymm/dense/LayerRegistry.h"

#include "synthetic_partition.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <variant>
#include <unistd.h>

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

TEST(LayerRegistryTest, EachKindWritesItsFilesCountsAndScoresWhatItHolds)
{
    using namespace hymm::dense::synthetic;
    namespace fs = std::filesystem;
    const fs::path root = fs::temp_directory_path() / ("hymm_layer_outputs_" + std::to_string(::getpid()));
    struct RemoveAtExit
    {
        fs::path p;
        ~RemoveAtExit() { fs::remove_all(p); }
    } cleanup{root};
    for (const LayerKind& k : layerKinds())
    {
        ASSERT_TRUE(k.outputs.write && k.outputs.scored_points && k.outputs.describe) << k.name;
        HybridMetricMap::Options o;
        for (const LayerKind& other : layerKinds()) o.*(other.enabled) = false;
        o.*(k.enabled) = true;
        WallWorld w;
        HybridMetricMap map(o);
        // A wall seen five times; the returns carry values (the property layer maps them).
        ScanPoints scan = wallScan(kVehicle, kMount, kWallX, kBeams, kHalfFov);
        scan.values.assign(scan.points.size(), 42.0);
        scan.value_stds.assign(scan.points.size(), 0.5);
        for (int i = 0; i < 5; ++i) map.insertScan(scan, kVehicle, w.partition);
        const LayerOutputContext c{map, w.partition, 5 * scan.points.size()};

        // What it scores lies on the wall (within a cell or a particle's spread).
        const auto scored = k.outputs.scored_points(c);
        EXPECT_GT(scored.size(), 10u) << k.name;
        for (const auto& p : scored) EXPECT_NEAR(p.x(), kWallX, 0.5) << k.name;

        // Its files carry its name and MRPT reads back every serialised one.
        const fs::path dir = root / k.name;
        fs::create_directories(dir);
        k.outputs.write(c, dir.string() + "/", true);
        size_t files = 0, objects = 0;
        for (const auto& f : fs::directory_iterator(dir))
        {
            ++files;
            const std::string name = f.path().filename().string();
            EXPECT_EQ(name.rfind(k.name, 0), 0u) << name;
            EXPECT_GT(fs::file_size(f.path()), 0u) << name;
            const std::string ext = f.path().extension().string();
            if (ext != ".bin" && ext != ".gridmap") continue;
            mrpt::io::CFileGZInputStream in(f.path().string());
            EXPECT_TRUE(mrpt::serialization::archiveFrom(in).ReadObject()) << name;
            ++objects;
        }
        EXPECT_GE(files, 2u) << k.name;
        EXPECT_GE(objects, 1u) << k.name;

        // Its counters say what it holds: as many Gaussians and at least as many particles
        // as it scores, the cells with a value, and no note that the scans carried none.
        if (k.outputs.counts)
        {
            std::map<std::string, std::variant<unsigned long, double, std::string>> counters;
            for (const auto& [name, value] : k.outputs.counts(c)) counters[name] = value;
            const auto count = [&](const char* name) { return std::get<unsigned long>(counters.at(name)); };
            const std::string kind = k.name;
            if (kind == "sog")
            {
                EXPECT_EQ(count("gaussians"), scored.size());
            }
            if (kind == "particles")
            {
                EXPECT_GE(count("particles"), scored.size());
            }
            if (kind == "occupancy")
            {
                EXPECT_GT(count("regions_fine") + count("regions_coarse"), 0u);
            }
            if (kind == "property")
            {
                EXPECT_EQ(count("rendered_cells"), scored.size());
                EXPECT_GT(count("cells"), 0u);
                EXPECT_EQ(counters.count("note"), 0u);
            }
        }
        std::ostringstream line;
        k.outputs.describe(line, c, 123);
        EXPECT_EQ(line.str().rfind("123 ", 0), 0u) << line.str();
    }
}

}  // namespace
