// CHybridMetricMap as an MRPT map on the wall scene (synthetic_partition.h): insertion,
// MRPT's likelihood on the rendered layers, serialisation round trip and bad files,
// creation through CMultiMetricMap from an .ini, and the named 3D objects (each of the five
// layers when enabled, none when not).
#include "synthetic_partition.h"

#include <gtest/gtest.h>
#include <hymm/dense/CHybridMetricMap.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileInputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

namespace
{
using hymm::dense::CHybridMetricMap;
using hymm::dense::HybridMetricMap;
using hymm::dense::FallbackFrame;
namespace synthetic = hymm::dense::synthetic;

// The wall scan of synthetic::wallScan as an MRPT observation (sensor 0.3 m ahead).
mrpt::obs::CObservation2DRangeScan wallObservation()
{
    const auto pts = synthetic::wallScan(synthetic::kVehicle, synthetic::kMount, synthetic::kWallX,
                                         synthetic::kBeams, synthetic::kHalfFov);
    mrpt::obs::CObservation2DRangeScan obs;
    obs.aperture = static_cast<float>(2 * synthetic::kHalfFov);
    obs.rightToLeft = true;
    obs.maxRange = 30.0f;
    obs.sensorPose = mrpt::poses::CPose3D(synthetic::kMount.x, synthetic::kMount.y, 0, 0, 0, 0);
    obs.resizeScan(pts.points.size());
    for (size_t k = 0; k < pts.points.size(); ++k)
    {
        obs.setScanRange(k, static_cast<float>(pts.points[k].norm()));
        obs.setScanRangeValidity(k, true);
    }
    return obs;
}

HybridMetricMap::Options pointsAndOccupancy()
{
    HybridMetricMap::Options o;
    o.enable_points = true;
    o.enable_occupancy = true;
    o.occupancy.cell_size_m = 0.1;
    return o;
}

struct Fixture
{
    synthetic::WallWorld world;
    CHybridMetricMap map;
    explicit Fixture(const HybridMetricMap::Options& o = pointsAndOccupancy())
    {
        hymm::dense::registerHybridMetricMap();
        HybridMetricMap empty(o);
        std::vector<CHybridMetricMap::Landmark> lms;
        for (const auto& [id, p] : world.lattice.landmarks())
            lms.push_back({id, p, 0.01 * 0.01 * Eigen::Matrix2d::Identity()});
        map.assign(world.partition, empty, lms);
    }
    mrpt::poses::CPose3D truth() const
    {
        return {synthetic::kVehicle.x, synthetic::kVehicle.y, 0, synthetic::kVehicle.phi, 0, 0};
    }
};

std::string tempFile(const std::string& name)
{
    return mrpt::system::getTempFileName() + "_" + name;
}

TEST(CHybridMetricMap, InsertedScanMakesTheTruePoseTheMostLikely)
{
    Fixture f;
    EXPECT_TRUE(f.map.isEmpty());
    const auto obs = wallObservation();
    ASSERT_TRUE(f.map.canComputeObservationLikelihood(obs) == false);  // nothing mapped yet
    ASSERT_TRUE(f.map.insertObservation(obs, f.truth()));
    EXPECT_FALSE(f.map.isEmpty());
    EXPECT_GT(f.map.renderedPoints().size(), 100u);
    ASSERT_TRUE(f.map.canComputeObservationLikelihood(obs));

    // The wall is x = 17: poses off in x or in heading explain the scan worse; along the
    // wall (y) the scan carries little information, so that direction is not tested.
    const double at_truth = f.map.computeObservationLikelihood(obs, f.truth());
    for (const auto& off : {mrpt::poses::CPose3D(0.3, 0, 0, 0, 0, 0), mrpt::poses::CPose3D(-0.3, 0, 0, 0, 0, 0),
                            mrpt::poses::CPose3D(0, 0, 0, 0.05, 0, 0), mrpt::poses::CPose3D(0, 0, 0, -0.05, 0, 0)})
        EXPECT_LT(f.map.computeObservationLikelihood(obs, f.truth() + off), at_truth - 1.0) << off;
    // A scan outside every region adds nothing.
    EXPECT_FALSE(f.map.insertObservation(obs, mrpt::poses::CPose3D(200, 200, 0, 0, 0, 0)));
}

TEST(CHybridMetricMap, FileRoundTripKeepsMapAndLikelihood)
{
    Fixture f;
    const auto obs = wallObservation();
    ASSERT_TRUE(f.map.insertObservation(obs, f.truth()));
    f.map.likelihood_resolution_m = 0.2;
    f.map.likelihoodOptions.LF_stdHit = 0.25f;
    const std::string file = tempFile("wall.hymm");
    f.map.saveToFile(file);
    const auto back = CHybridMetricMap::loadFromFile(file);
    EXPECT_EQ(back->partition().size(), f.map.partition().size());
    EXPECT_EQ(back->dense().size(), f.map.dense().size());
    ASSERT_EQ(back->landmarks().size(), f.map.landmarks().size());
    EXPECT_EQ(back->landmarks()[3].mean, f.map.landmarks()[3].mean);
    EXPECT_DOUBLE_EQ(back->likelihood_resolution_m, 0.2);
    EXPECT_FLOAT_EQ(back->likelihoodOptions.LF_stdHit, 0.25f);
    EXPECT_EQ(back->renderedPoints().size(), f.map.renderedPoints().size());
    for (double dx : {0.0, 0.2, -0.4})
    {
        const mrpt::poses::CPose3D p = f.truth() + mrpt::poses::CPose3D(dx, 0.1, 0, 0.02, 0, 0);
        EXPECT_DOUBLE_EQ(back->computeObservationLikelihood(obs, p), f.map.computeObservationLikelihood(obs, p));
    }
    // A copy (clone) is as good as the original.
    const CHybridMetricMap copy(*back);
    EXPECT_DOUBLE_EQ(copy.computeObservationLikelihood(obs, f.truth()),
                     f.map.computeObservationLikelihood(obs, f.truth()));
    std::remove(file.c_str());
}

// Returns beyond the lattice's top edge (y = 15) kept in fallback tiles of the regions
// below them travel with the map: in copies and through map.hymm (version 1).
TEST(CHybridMetricMap, FallbackTilesRoundTripThroughTheFile)
{
    Fixture f;
    HybridMetricMap::Options o;
    o.enable_points = true;
    o.enable_occupancy = true;
    o.occupancy.cell_size_m = 0.1;
    o.fallback_max_distance_m = 5;
    o.fallback_frame = FallbackFrame::Rigid;  // not the default: the file must keep it
    HybridMetricMap dense(o);
    for (double x = 6; x <= 14; x += 0.5)
        ASSERT_TRUE(dense.insertFallbackReturn({10, 10}, {x, 16.5}, 0.1, 0.017, f.world.partition));
    ASSERT_GT(dense.fallbackTiles(), 0u);
    CHybridMetricMap map;
    map.assign(f.world.partition, dense, f.map.landmarks());
    EXPECT_EQ(map.dense().fallbackTiles(), dense.fallbackTiles());
    // The tiles' returns are part of the rendered map (nothing else is mapped).
    EXPECT_EQ(map.renderedPoints().size(), 17u);

    const std::string file = tempFile("tiles.hymm");
    map.saveToFile(file);
    const auto back = CHybridMetricMap::loadFromFile(file);
    EXPECT_EQ(back->dense().fallbackTiles(), dense.fallbackTiles());
    EXPECT_EQ(back->dense().options().fallback_frame, FallbackFrame::Rigid);
    ASSERT_EQ(back->renderedPoints().size(), 17u);
    for (size_t i = 0; i < 17; ++i)
    {
        float x0, y0, x1, y1;
        map.renderedPoints().getPoint(i, x0, y0);
        back->renderedPoints().getPoint(i, x1, y1);
        EXPECT_EQ(x0, x1);
        EXPECT_EQ(y0, y1);
    }
    std::ostringstream a, b;
    map.dense().saveFallbackTiles(a);
    back->dense().saveFallbackTiles(b);
    EXPECT_EQ(a.str(), b.str());
    const CHybridMetricMap copy(*back);
    EXPECT_EQ(copy.dense().fallbackTiles(), dense.fallbackTiles());
    std::remove(file.c_str());

    // Malformed tile text is an error naming the tile.
    std::istringstream bad("fallback_tiles 1\ntile 0 0 0 7\n");
    EXPECT_THROW(HybridMetricMap(o).loadFallbackTiles(bad), std::runtime_error);
}

TEST(CHybridMetricMap, BadFilesAreClearErrors)
{
    Fixture f;
    ASSERT_TRUE(f.map.insertObservation(wallObservation(), f.truth()));
    EXPECT_THROW(CHybridMetricMap::loadFromFile("/nonexistent/map.hymm"), std::runtime_error);

    // Truncated: the first half of a valid (uncompressed) file.
    const std::string full = tempFile("full.hymm");
    {
        mrpt::io::CFileOutputStream out(full);
        auto arch = mrpt::serialization::archiveFrom(out);
        arch << f.map;
    }
    std::ifstream in(full, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string cut = tempFile("cut.hymm");
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
    EXPECT_THROW(CHybridMetricMap::loadFromFile(cut), std::runtime_error);
    EXPECT_NO_THROW(CHybridMetricMap::loadFromFile(full));  // the uncompressed file itself is fine

    // Another class.
    const std::string other = tempFile("points.bin");
    {
        mrpt::io::CFileGZOutputStream out(other);
        auto arch = mrpt::serialization::archiveFrom(out);
        arch << f.map.renderedPoints();
    }
    try
    {
        CHybridMetricMap::loadFromFile(other);
        ADD_FAILURE() << "a CSimplePointsMap was read as a HYMM map";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("CSimplePointsMap"), std::string::npos) << e.what();
    }
    for (const auto& p : {full, cut, other}) std::remove(p.c_str());
}

TEST(CHybridMetricMap, CMultiMetricMapCreatesItFromIni)
{
    Fixture f;
    const auto obs = wallObservation();
    ASSERT_TRUE(f.map.insertObservation(obs, f.truth()));
    const std::string file = tempFile("ini.hymm");
    f.map.saveToFile(file);
    mrpt::config::CConfigFileMemory ini(
        "[MAP]\nHybridMetricMap_count = 1\n"
        "[MAP_HybridMetricMap_00]\nmap_file = " + file + "\nlikelihood_resolution_m = 0.1\n"
        "[MAP_HybridMetricMap_00_likelihoodOpts]\nLF_stdHit = 0.2\n");
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(ini, "MAP");
    ASSERT_EQ(inits.size(), 1u);
    mrpt::maps::CMultiMetricMap multi;
    multi.setListOfMaps(inits);
    const auto m = multi.mapByClass<CHybridMetricMap>();
    ASSERT_TRUE(m);
    EXPECT_EQ(m->dense().size(), f.map.dense().size());
    EXPECT_FLOAT_EQ(m->likelihoodOptions.LF_stdHit, 0.2f);
    f.map.likelihoodOptions.LF_stdHit = 0.2f;
    EXPECT_DOUBLE_EQ(multi.computeObservationLikelihood(obs, f.truth()),
                     f.map.computeObservationLikelihood(obs, f.truth()));

    // Without map_file: an empty map of the given dense options.
    mrpt::config::CConfigFileMemory empty_ini(
        "[MAP]\nCHybridMetricMap_count = 1\n[MAP_CHybridMetricMap_00_HybridMetricMap]\nenable_points = false\n");
    mrpt::maps::TSetOfMetricMapInitializers e;
    e.loadFromConfigFile(empty_ini, "MAP");
    mrpt::maps::CMultiMetricMap multi2;
    multi2.setListOfMaps(e);
    const auto m2 = multi2.mapByClass<CHybridMetricMap>();
    ASSERT_TRUE(m2);
    EXPECT_TRUE(m2->isEmpty());
    EXPECT_FALSE(m2->dense().options().enable_points);
    std::remove(file.c_str());
}

// The map definition read by MRPT's apps (CMultiMetricMap): a bad resolution is an
// error quoting the value as written, not a number MRPT's parser made of it. Loaded
// directly: through TSetOfMetricMapInitializers, MRPT 2.5 leaks the definition it was
// filling when the load throws (LeakSanitizer).
TEST(CHybridMetricMap, BadLikelihoodResolutionIsAnErrorQuotingTheValue)
{
    const auto ini = [](const std::string& value) {
        return mrpt::config::CConfigFileMemory("[MAP_00]\nlikelihood_resolution_m = " + value + "\n");
    };
    for (const std::string bad : {"abc", "0.1m", "-0.2", "50", "nan"})
    {
        CHybridMetricMap::TMapDefinition def;
        try
        {
            def.loadFromConfigFile(ini(bad), "MAP_00");
            ADD_FAILURE() << "accepted " << bad;
        }
        catch (const std::exception& e)
        {
            EXPECT_NE(std::string(e.what()).find("likelihood_resolution_m=" + bad + ":"), std::string::npos)
                << e.what();
        }
    }
    CHybridMetricMap::TMapDefinition def;
    def.loadFromConfigFile(ini("0.25"), "MAP_00");
    EXPECT_DOUBLE_EQ(def.likelihood_resolution_m, 0.25);
}

TEST(CHybridMetricMap, VisualizationHasOneNamedObjectPerPart)
{
    Fixture f;
    ASSERT_TRUE(f.map.insertObservation(wallObservation(), f.truth()));
    mrpt::opengl::CSetOfObjects o;
    f.map.getVisualizationInto(o);
    for (const char* name : {"ltr_triangles", "landmarks", "occupancy", "points"})
        EXPECT_TRUE(o.getByName(name)) << name;
    const auto tri = std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(o.getByName("ltr_triangles"));
    ASSERT_TRUE(tri);
    EXPECT_EQ(tri->getLineCount(), 3 * f.map.partition().size());
    const auto lms = std::dynamic_pointer_cast<mrpt::opengl::CSetOfObjects>(o.getByName("landmarks"));
    ASSERT_TRUE(lms);
    EXPECT_EQ(lms->size(), f.map.landmarks().size() + 1);  // ellipses and the means

    const std::string prefix = tempFile("repr");
    f.map.saveMetricMapRepresentationToFile(prefix);
    for (const char* s : {"_occupancy.png", "_points.txt", "_landmarks.txt", "_regions.txt"})
        EXPECT_TRUE(mrpt::system::fileExists(prefix + s)) << s;
}

// Every layer enabled, the scan carrying an intensity (the property layer's value): each
// layer is its named object and holds something; a layer that is off has no object.
TEST(CHybridMetricMap, VisualizationHasANonEmptyObjectPerEnabledLayer)
{
    auto o = pointsAndOccupancy();
    o.enable_particles = o.enable_sog = o.enable_property = true;
    Fixture f(o);
    auto obs = wallObservation();
    obs.setScanHasIntensity(true);
    for (size_t k = 0; k < obs.getScanSize(); ++k) obs.setScanIntensity(k, static_cast<int32_t>(10 + k % 7));
    ASSERT_TRUE(f.map.insertObservation(obs, f.truth()));
    mrpt::opengl::CSetOfObjects scene;
    f.map.getVisualizationInto(scene);

    const auto occupancy = std::dynamic_pointer_cast<mrpt::opengl::CSetOfObjects>(scene.getByName("occupancy"));
    ASSERT_TRUE(occupancy);
    EXPECT_GT(occupancy->size(), 0u);
    const auto points = std::dynamic_pointer_cast<mrpt::opengl::CPointCloud>(scene.getByName("points"));
    ASSERT_TRUE(points);
    EXPECT_EQ(points->size(), f.map.renderedPoints().size());
    EXPECT_GT(points->size(), 100u);
    const auto particles = std::dynamic_pointer_cast<mrpt::opengl::CPointCloudColoured>(scene.getByName("particles"));
    ASSERT_TRUE(particles);
    EXPECT_GT(particles->size(), 100u);
    const auto sog = std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(scene.getByName("sog"));
    ASSERT_TRUE(sog);
    EXPECT_GT(sog->getLineCount(), 0u);
    const auto property = std::dynamic_pointer_cast<mrpt::opengl::CPointCloudColoured>(scene.getByName("property"));
    ASSERT_TRUE(property);
    EXPECT_GT(property->size(), 0u);
    // Drawn where the scan hit: every property cell is near the wall x = kWallX.
    for (size_t i = 0; i < property->size(); ++i)
        EXPECT_NEAR(property->getPoint3Df(i).x, synthetic::kWallX, 1.0) << i;

    // The points-and-occupancy map draws neither of the three other layers.
    Fixture two;
    ASSERT_TRUE(two.map.insertObservation(wallObservation(), two.truth()));
    mrpt::opengl::CSetOfObjects scene2;
    two.map.getVisualizationInto(scene2);
    for (const char* off : {"particles", "sog", "property"}) EXPECT_FALSE(scene2.getByName(off)) << off;
    EXPECT_TRUE(scene2.getByName("points"));
}

}  // namespace
