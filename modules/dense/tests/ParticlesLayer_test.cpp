/**
 * @file ParticlesLayer_test.cpp
 * @brief Particle layer (Sec. 4.2): walls become heavy particles, a vacated area loses
 *        its particles through the free-space step, the association / Bayes update /
 *        position averaging of Eq. 4.10-4.12 exactly, subsampling and persistence.
 */
#include "hymm/dense/ParticlesLayer.h"

#include <gtest/gtest.h>
#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/maps/CSimplePointsMap.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>

namespace
{
using namespace hymm::dense;
using V2 = Eigen::Vector2d;
const hymm::ltr::TriangleFrame::Vertices kRef{{V2(0, -20), V2(30, 0), V2(0, 20)}};

/** Beams every 0.5 deg over +-half_fov_deg from the origin onto the wall x = wall_x,
 *  blocked by the segment x = object_x, |y| <= 1 when given. */
RegionScan scanOf(double wall_x, std::optional<double> object_x, double half_fov_deg = 15)
{
    RegionScan s;
    s.sensor = V2(0, 0);
    for (double deg = -half_fov_deg; deg <= half_fov_deg + 1e-9; deg += 0.5)
    {
        const V2 u(std::cos(deg * M_PI / 180), std::sin(deg * M_PI / 180));
        double r = wall_x / u.x();
        if (object_x && std::abs(*object_x * u.y() / u.x()) <= 1.0) r = *object_x / u.x();
        const V2 hit = r * u;
        s.hits.push_back(hit);
        FreeRay ray{s.sensor, hit, true};
        ray.beam_end = hit;
        ray.beam_hit = true;
        s.rays.push_back(ray);
    }
    return s;
}

std::vector<ParticlesLayer::Particle> near(const ParticlesLayer& l, double x, double dx, double max_abs_y)
{
    std::vector<ParticlesLayer::Particle> out;
    for (const auto& p : l.particles())
        if (std::abs(p.position.x() - x) < dx && std::abs(p.position.y()) < max_abs_y) out.push_back(p);
    return out;
}

TEST(ParticlesLayerTest, RepeatedWallHitsGiveHeavyParticlesOnTheWall)
{
    ParticlesLayer layer(ParticlesLayer::Options{}, kRef);
    for (int k = 0; k < 20; ++k) layer.insert(scanOf(10.0, std::nullopt));
    const auto on_wall = near(layer, 10.0, 0.05, 2.0);
    ASSERT_GT(on_wall.size(), 200u);
    size_t heavy = 0;
    double sum = 0;
    for (const auto& p : on_wall)
    {
        heavy += p.weight > 0.8;
        sum += p.weight;
    }
    EXPECT_GT(static_cast<double>(heavy) / static_cast<double>(on_wall.size()), 0.8);
    EXPECT_GT(sum / static_cast<double>(on_wall.size()), 0.8);
    // Particles well in front of the wall describe free space: light.
    // (The occupancy model is < 0.5 everywhere in front of a return, Eq. 4.4.)
    const auto in_front = near(layer, 9.6, 0.15, 2.0);
    for (const auto& p : in_front) EXPECT_LE(p.weight, 0.5) << p.position.transpose();
    // All particles come from the sensor model around the wall.
    for (const auto& p : layer.particles()) EXPECT_NEAR(p.position.x(), 10.0, 0.6);
}

TEST(ParticlesLayerTest, VacatedAreaLosesItsParticles)
{
    for (const bool free_step : {true, false})
    {
        ParticlesLayer::Options o;
        o.free_space_update = free_step;
        ParticlesLayer layer(o, kRef);
        for (int k = 0; k < 10; ++k) layer.insert(scanOf(10.0, 6.0));
        ASSERT_GT(near(layer, 6.0, 0.3, 0.9).size(), 100u);
        // The object is gone: beams now pass through its area to the wall.
        for (int k = 0; k < 20; ++k) layer.insert(scanOf(10.0, std::nullopt));
        if (free_step)
        {
            EXPECT_EQ(near(layer, 6.0, 0.3, 0.9).size(), 0u);
            EXPECT_GT(near(layer, 10.0, 0.05, 0.9).size(), 50u);  // the wall stays
        }
        else
            EXPECT_GT(near(layer, 6.0, 0.3, 0.9).size(), 100u);  // control: stays occupied
    }
}

TEST(ParticlesLayerTest, AssociationBayesUpdateAndAveragingFollowEquations410To412)
{
    ParticlesLayer::Options o;
    o.samples_per_return = 1;
    RegionScan scan;
    scan.sensor = V2(0, 0);
    scan.hits = {V2(5, 0)};
    scan.range_std_m = 0.02;
    scan.bearing_std_rad = 0.002;
    FreeRay ray{V2(0, 0), V2(5, 0), true};
    ray.beam_end = V2(5, 0);
    ray.beam_hit = true;
    scan.rays = {ray};

    // Same seed and reference: both layers draw the same sample.
    ParticlesLayer fresh(o, kRef);
    fresh.insert(scan);
    ASSERT_EQ(fresh.size(), 1u);
    const ParticlesLayer::Particle s = fresh.particles()[0];  // Eq. 4.12: kept with w_i
    EXPECT_NEAR(s.position.x(), 5.0, 0.1);
    EXPECT_GT(s.weight, 0.0);

    ParticlesLayer layer(o, kRef);
    std::stringstream prior;
    prior << std::hexfloat << "particles 3\n"
          << s.position.x() + 0.1 << ' ' << s.position.y() << " 0.6\n"  // within d_min of the sample
          << "5.6 0 0.7\n"                                              // beyond d_min, behind the return
          << "3 0 0.8\n";                                               // in the beam's free space
    layer.load(prior);
    layer.insert(scan);
    ASSERT_EQ(layer.size(), 3u);  // the sample updated a prior particle and was consumed
    const auto& ps = layer.particles();
    // Eq. 4.11 (corrected) and the position averaging of Sec. 4.2.3.
    EXPECT_NEAR(ps[0].weight, bayesOccupancyUpdate(0.6, s.weight), 1e-12);
    EXPECT_LT((ps[0].position - (s.position + V2(0.05, 0))).norm(), 1e-12);
    EXPECT_EQ(ps[1].weight, 0.7);  // behind the return: unknown, untouched
    const double free_p = occupancyModel(3, 0, 5, 0, true, {0.02, 0.002}, o.profile());
    ASSERT_LT(free_p, 0.31);
    EXPECT_NEAR(ps[2].weight, bayesOccupancyUpdate(0.8, free_p), 1e-12);
    EXPECT_EQ(layer.lastUpdate().associated, 1u);
    EXPECT_EQ(layer.lastUpdate().free_updated, 1u);
    EXPECT_EQ(layer.lastUpdate().added, 0u);
}

TEST(ParticlesLayerTest, CellCapLevelsOffOnRevisitsAndKeepsTheWall)
{
    // The same wall seen again and again (a region revisited lap after lap): without the
    // cap every scan adds the samples no particle took; with it the count levels off.
    ParticlesLayer::Options o;
    o.max_per_cell = 4;
    ParticlesLayer capped(o, kRef);
    o.max_per_cell = 0;
    ParticlesLayer thesis(o, kRef);
    std::vector<size_t> n_capped, n_thesis;
    for (int k = 0; k < 40; ++k)
    {
        capped.insert(scanOf(10.0, std::nullopt));
        thesis.insert(scanOf(10.0, std::nullopt));
        n_capped.push_back(capped.size());
        n_thesis.push_back(thesis.size());
    }
    EXPECT_GT(n_thesis[39], n_thesis[19] + (n_thesis[19] - n_thesis[9]) / 2);  // still growing
    EXPECT_LE(n_capped[39], n_capped[19] + n_capped[19] / 50);                   // levelled off
    EXPECT_LT(n_capped[39], n_thesis[39] / 2);
    // At most 4 per d_min cell, and the wall is still where the heavy particles are.
    std::map<std::pair<long, long>, int> per_cell;
    for (const auto& p : capped.particles())
    {
        const std::pair<long, long> cell(std::lround(std::floor(p.position.x() / o.d_min_m)),
                                         std::lround(std::floor(p.position.y() / o.d_min_m)));
        EXPECT_LE(++per_cell[cell], 4);
    }
    const auto on_wall = near(capped, 10.0, 0.1, 2.0);
    ASSERT_GT(on_wall.size(), 50u);
    for (const auto& p : on_wall) EXPECT_GT(p.weight, 0.5);
}

TEST(ParticlesLayerTest, SubsamplingBoundsTheCountAndKeepsTheHeaviest)
{
    ParticlesLayer::Options o;
    o.max_particles = 300;
    ParticlesLayer layer(o, kRef);
    ParticlesLayer unbounded(ParticlesLayer::Options{}, kRef);
    for (int k = 0; k < 5; ++k)
    {
        layer.insert(scanOf(10.0, std::nullopt));
        unbounded.insert(scanOf(10.0, std::nullopt));
        EXPECT_LE(layer.size(), 300u);
    }
    ASSERT_GT(unbounded.size(), 300u);
    double mean_b = 0, mean_u = 0;
    for (const auto& p : layer.particles()) mean_b += p.weight / static_cast<double>(layer.size());
    for (const auto& p : unbounded.particles()) mean_u += p.weight / static_cast<double>(unbounded.size());
    EXPECT_GT(mean_b, mean_u);
}

TEST(ParticlesLayerTest, RenderSaveLoadAndBadInput)
{
    ParticlesLayer::Options o;
    o.render_min_weight = 0.5;
    ParticlesLayer layer(o, kRef);
    for (int k = 0; k < 3; ++k) layer.insert(scanOf(10.0, std::nullopt));
    const auto heavy = static_cast<size_t>(std::count_if(
        layer.particles().begin(), layer.particles().end(), [](const auto& p) { return p.weight >= 0.5; }));
    mrpt::maps::CPointsMapXYZI pts;
    layer.renderInto(hymm::ltr::AffineRegionMap(), pts);
    ASSERT_EQ(pts.size(), heavy);
    for (size_t i = 0; i < pts.size(); ++i) EXPECT_GE(pts.getPointIntensity(i), 0.5f);

    std::stringstream ss;
    layer.save(ss);
    ParticlesLayer copy(o, kRef);
    copy.load(ss);
    std::stringstream a, b;
    layer.save(a);
    copy.save(b);
    EXPECT_EQ(a.str(), b.str());
    std::stringstream bad("particles 1\n1 2 1.5\n");
    EXPECT_THROW(copy.load(bad), std::runtime_error);

    RegionScan s = scanOf(10.0, std::nullopt);
    s.range_std_m = -1;
    EXPECT_THROW(layer.insert(s), std::invalid_argument);
    s = scanOf(10.0, std::nullopt);
    s.sensor.x() = std::nan("");
    EXPECT_THROW(layer.insert(s), std::invalid_argument);
}

}  // namespace
