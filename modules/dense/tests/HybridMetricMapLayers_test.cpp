/**
 * @file HybridMetricMapLayers_test.cpp
 * @brief The particle, SOG and property layers inside HybridMetricMap: built per region
 *        when enabled, fed with noise and values through RegionScan, rendered globally,
 *        saved / loaded, configured strictly; background coarsening of idle regions.
 */
#include "hymm/dense/HybridMetricMap.h"

#include "hymm/dense/map_images.h"
#include "hymm/dense/outline_metrics.h"
#include "synthetic_partition.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CHeightGridMap2D.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace
{
using namespace hymm::dense;
using namespace hymm::dense::synthetic;
using V2 = Eigen::Vector2d;

HybridMetricMap::Options allLayers()
{
    HybridMetricMap::Options o;
    o.enable_particles = o.enable_sog = o.enable_property = true;
    o.property.cell_size_m = 0.25;
    return o;
}

/** Wall scan whose returns carry intensity 50 + y (a ramp along the wall). */
ScanPoints wallScanWithValues()
{
    ScanPoints s = wallScan(kVehicle, kMount, kWallX, kBeams, kHalfFov);
    const auto w = s.toWorld(kVehicle, 100.0);
    for (const auto& b : w.beams) s.values.push_back(50.0 + b.end.y());
    s.value_stds.assign(s.values.size(), 0.5);
    s.range_std_m = 0.05;
    s.bearing_std_rad = 0.5 * M_PI / 180;
    return s;
}

TEST(HybridMetricMapLayersTest, AllLayersAreBuiltFedAndRendered)
{
    WallWorld w;
    HybridMetricMap map(allLayers());
    const ScanPoints scan = wallScanWithValues();
    for (int k = 0; k < 5; ++k) map.insertScan(scan, kVehicle, w.partition);
    size_t with_hits = 0;
    for (const long id : map.regionIds())
    {
        const auto* lm = map.localMap(id);
        EXPECT_EQ(lm->layerKinds(), (std::vector<std::string>{"points", "occupancy", "particles", "sog", "property"}));
        with_hits += lm->layer("sog")->size() > 0;
    }
    EXPECT_GE(with_hits, 3u);

    mrpt::maps::CSimplePointsMap particles, means;
    map.renderLayer(ParticlesLayer::kKind, w.partition, particles);
    map.renderLayer(SogLayer::kKind, w.partition, means);
    ASSERT_GT(particles.size(), 1000u);
    for (const V2& p : pointsOf(particles)) EXPECT_NEAR(p.x(), kWallX, 0.5);
    ASSERT_GT(means.size(), 100u);
    for (const V2& p : pointsOf(means)) EXPECT_NEAR(p.x(), kWallX, 0.05);

    ScalarField surface;
    map.renderSogSurface(w.partition, 0.1, surface);
    EXPECT_GT(surface.at(V2(kWallX, 7.5)), 0.5);
    EXPECT_LT(surface.at(V2(10.0, 7.5)), 1e-6);
    const auto ells = map.renderSogEllipses(w.partition, 12);
    EXPECT_EQ(ells.size(), means.size());

    ScalarField mean, sd;
    map.renderProperty(w.partition, 0.25, mean, sd);
    size_t seen = 0;
    for (int iy = 0; iy < mean.sizeY(); ++iy)
        for (int ix = 0; ix < mean.sizeX(); ++ix)
        {
            if (std::isnan(mean.values(iy, ix))) continue;
            ++seen;
            const V2 c = mean.cellCentre(ix, iy);
            EXPECT_NEAR(c.x(), kWallX, 0.3);
            EXPECT_NEAR(mean.values(iy, ix), 50.0 + c.y(), 0.3);  // within the cell's ramp
            EXPECT_LT(sd.values(iy, ix), 0.5 / std::sqrt(5.0) + 1e-9);  // >= 5 fused values
        }
    EXPECT_GT(seen, 30u);
    mrpt::maps::CHeightGridMap2D hg(mrpt::maps::CHeightGridMap2D::mrSimpleAverage, 0, 20, 0, 15, 0.25);
    map.renderLayer(PropertyLayer::kKind, w.partition, hg);
    EXPECT_NEAR(hg.cellByPos(kWallX + 0.1, 7.6)->h, 57.6, 0.3);

    // Wrong targets are refused.
    mrpt::maps::COccupancyGridMap2D og;
    EXPECT_THROW(map.renderLayer(ParticlesLayer::kKind, w.partition, og), std::invalid_argument);
    EXPECT_THROW(map.renderLayer(PropertyLayer::kKind, w.partition, particles), std::invalid_argument);

    const auto by_kind = map.memoryBytesByKind();
    for (const char* k : {"points", "occupancy", "particles", "sog", "property"}) EXPECT_GT(by_kind.at(k), 0u) << k;

    const std::string dir = ::testing::TempDir();
    saveScalarFieldPng(surface, dir + "dense_sog.png", 0.0, 1.0, &w.partition, &ells);
    saveScalarFieldPng(mean, dir + "dense_prop.png", 40.0, 65.0);
    std::ifstream in(dir + "dense_sog.png", std::ios::binary);
    char sig[4] = {};
    in.read(sig, 4);
    EXPECT_EQ(std::string(sig + 1, 3), "PNG");
}

TEST(HybridMetricMapLayersTest, SaveLoadRoundTripWithAllLayers)
{
    WallWorld w;
    HybridMetricMap map(allLayers());
    map.insertScan(wallScanWithValues(), kVehicle, w.partition);
    map.insertScan(wallScanWithValues(), kVehicle, w.partition);
    std::stringstream ss;
    map.save(ss);
    HybridMetricMap copy(allLayers());
    copy.load(ss);
    std::stringstream s1, s2;
    map.save(s1);
    copy.save(s2);
    EXPECT_EQ(s1.str(), s2.str());
    EXPECT_NE(s1.str().find("layer particles"), std::string::npos);
    EXPECT_NE(s1.str().find("layer sog"), std::string::npos);
    EXPECT_NE(s1.str().find("layer property"), std::string::npos);
    // A map without the particle layer cannot read a file that has one.
    auto o = allLayers();
    o.enable_particles = false;
    HybridMetricMap other(o);
    std::stringstream again(s1.str());
    EXPECT_THROW(other.load(again), std::runtime_error);
}

TEST(HybridMetricMapLayersTest, BadScanValuesAreRejectedBeforeAnyChange)
{
    WallWorld w;
    HybridMetricMap map(allLayers());
    ScanPoints scan = wallScanWithValues();
    scan.values[7] = std::nan("");
    EXPECT_THROW(map.insertScan(scan, kVehicle, w.partition), std::invalid_argument);
    scan = wallScanWithValues();
    scan.value_stds[3] = 0;
    EXPECT_THROW(map.insertScan(scan, kVehicle, w.partition), std::invalid_argument);
    scan = wallScanWithValues();
    scan.range_std_m = -0.1;
    EXPECT_THROW(map.insertScan(scan, kVehicle, w.partition), std::invalid_argument);
    EXPECT_EQ(map.size(), 0u);
}

TEST(HybridMetricMapLayersTest, IdleAlmostEmptyRegionsAreCoarsened)
{
    WallWorld w;
    auto o = allLayers();
    o.occupancy.coarse_cell_size_m = 0.5;
    // Unknown and free cells count as empty (P < 0.55): only occupied cells keep a
    // region fine, so regions the beams merely crossed qualify.
    o.occupancy.coarsen_min_prob = 0.55;
    HybridMetricMap map(o);
    const ScanPoints scan = wallScanWithValues();
    map.insertScan(scan, kVehicle, w.partition);
    // An empty report while every region was touched by the last scan.
    EXPECT_TRUE(map.coarsenIdleRegions().coarsened.empty());

    // A scan far away touches none of the wall regions: now they are idle.
    ScanPoints far;
    far.points = {V2(1.0, 0.0)};
    map.insertScan(far, {1.0, 1.0, 0.0}, w.partition);
    const auto before_kind = map.memoryBytesByKind();
    const auto rep = map.coarsenIdleRegions();
    ASSERT_GT(rep.coarsened.size(), 0u);
    EXPECT_LT(rep.bytesAfter(), rep.bytesBefore());
    EXPECT_LT(map.memoryBytesByKind().at("occupancy"), before_kind.at("occupancy"));
    EXPECT_EQ(map.memoryBytesByKind().at("points"), before_kind.at("points"));
    for (const auto& r : rep.coarsened)
    {
        const auto* occ = map.localMap(r.id)->layerAs<OccupancyLayer>(OccupancyLayer::kKind);
        EXPECT_TRUE(occ->isCoarse());
        EXPECT_LT(occ->freeFraction(0.55), 1.0 + 1e-12);
    }
    // Regions holding the wall keep their resolution and the wall stays occupied.
    size_t fine_with_wall = 0;
    for (const long id : map.regionIds())
    {
        const auto* occ = map.localMap(id)->layerAs<OccupancyLayer>(OccupancyLayer::kKind);
        if (!occ->isCoarse() && map.localMap(id)->layer("points")->size() > 10) ++fine_with_wall;
    }
    EXPECT_GT(fine_with_wall, 0u);
    mrpt::maps::COccupancyGridMap2D og;
    map.renderOccupancy(w.partition, 0.1, og);
    EXPECT_GT(og.getPos(static_cast<float>(kWallX), 7.55f), 0.6f);
    EXPECT_TRUE(map.coarsenIdleRegions().coarsened.empty());  // nothing left to coarsen

    // Periodic coarsening from insertScan.
    o.coarsen_every_n_scans = 2;
    HybridMetricMap periodic(o);
    EXPECT_EQ(periodic.insertScan(scan, kVehicle, w.partition).regions_coarsened, 0u);
    EXPECT_GT(periodic.insertScan(far, {1.0, 1.0, 0.0}, w.partition).regions_coarsened, 0u);
}

TEST(HybridMetricMapLayersTest, OptionsLoadSaveAndRejectMalformedKeys)
{
    mrpt::config::CConfigFileMemory cfg(
        "[HybridMetricMap]\nenable_particles=true\nenable_sog=yes\nenable_property=1\ncoarsen_every_n_scans=10\n"
        "[OccupancyLayer]\ncoarse_cell_size_m=0.5\ncoarsen_cells_percent=0.95\ncoarsen_min_prob=0.25\n"
        "[ParticlesLayer]\nsamples_per_return=7\nd_min_m=0.3\nmax_particles=1000\nbearing_std_deg=2\n"
        "[SogLayer]\nk=0.5\nfusion_rule=product\n"
        "[PropertyLayer]\ncell_size_m=0.3\ndefault_value_std=4\n");
    HybridMetricMap::Options o;
    o.loadAll(cfg);
    EXPECT_TRUE(o.enable_particles && o.enable_sog && o.enable_property);
    EXPECT_EQ(o.coarsen_every_n_scans, 10);
    EXPECT_DOUBLE_EQ(o.occupancy.coarsen_cells_percent, 0.95);
    EXPECT_EQ(o.particles.samples_per_return, 7);
    EXPECT_DOUBLE_EQ(o.particles.noise().bearing_std_rad, 2 * M_PI / 180);
    EXPECT_EQ(o.sog.fusion_rule, SogLayer::FusionRule::Product);
    EXPECT_DOUBLE_EQ(o.property.default_value_std, 4);

    mrpt::config::CConfigFileMemory saved;
    o.saveAll(saved);
    HybridMetricMap::Options back;
    back.loadAll(saved);
    EXPECT_EQ(back.particles.max_particles, 1000);
    EXPECT_EQ(back.sog.fusion_rule, SogLayer::FusionRule::Product);
    EXPECT_DOUBLE_EQ(back.occupancy.coarse_cell_size_m, 0.5);
    EXPECT_DOUBLE_EQ(back.property.cell_size_m, 0.3);

    const auto load = [](const std::string& text) {
        mrpt::config::CConfigFileMemory c(text);
        HybridMetricMap::Options x;
        x.loadAll(c);
    };
    EXPECT_NO_THROW(load("[HybridMetricMap]\nenable_points=false\nenable_occupancy=false\nenable_sog=true\n"));
    EXPECT_THROW(load("[HybridMetricMap]\nenable_particle=true\n"), std::exception);
    EXPECT_THROW(load("[HybridMetricMap]\ncoarsen_every_n_scans=-1\n"), std::exception);
    EXPECT_THROW(load("[ParticlesLayer]\nd_min=0.2\n"), std::exception);
    EXPECT_THROW(load("[ParticlesLayer]\nsamples_per_return=0\n"), std::exception);
    EXPECT_THROW(load("[ParticlesLayer]\nprob_min=0.6\n"), std::exception);
    EXPECT_THROW(load("[ParticlesLayer]\nrange_std_m=nan\n"), std::exception);
    EXPECT_THROW(load("[ParticlesLayer]\nmax_weight=0.5\n"), std::exception);
    EXPECT_THROW(load("[SogLayer]\nfusion_rule=multiply\n"), std::exception);
    EXPECT_THROW(load("[SogLayer]\nk=0\n"), std::exception);
    EXPECT_THROW(load("[SogLayer]\nsigma=1\n"), std::exception);
    EXPECT_THROW(load("[PropertyLayer]\ndefault_value_std=0\n"), std::exception);
    EXPECT_THROW(load("[PropertyLayer]\ncell=0.2\n"), std::exception);
    EXPECT_THROW(load("[OccupancyLayer]\ncoarse_cell_size_m=0.05\n"), std::exception);  // finer than cells
    EXPECT_THROW(load("[OccupancyLayer]\ncoarsen_cells_percent=1.5\n"), std::exception);
}

}  // namespace
