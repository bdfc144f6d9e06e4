/**
 * @file PropertyLayer_test.cpp
 * @brief Inverse-variance fusion per cell, input checks, intensities from an MRPT
 *        range scan, rendering into CHeightGridMap2D and persistence, and noisy
 *        intensities of a wall recovered through HybridMetricMap.
 */
#include "hymm/dense/HybridMetricMap.h"
#include "hymm/dense/PropertyLayer.h"
#include "hymm/dense/ScanPoints.h"
#include "synthetic_partition.h"

#include <gtest/gtest.h>
#include <mrpt/maps/CHeightGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

namespace
{
using namespace hymm::dense;
using V2 = Eigen::Vector2d;
const hymm::ltr::TriangleFrame::Vertices kRef{{V2(0, 0), V2(4, 0), V2(0, 4)}};

PropertyLayer::Options opts()
{
    PropertyLayer::Options o;
    o.cell_size_m = 0.5;
    o.default_value_std = 2.0;
    return o;
}

TEST(PropertyLayerTest, FusionIsTheInverseVarianceWeightedMean)
{
    PropertyLayer layer(opts(), kRef);
    RegionScan s;
    s.hits = {V2(1.1, 1.1), V2(1.2, 1.3), V2(1.4, 1.05), V2(3.1, 0.2)};
    s.hit_values = {10.0, 14.0, 11.0, -3.0};
    s.hit_value_stds = {1.0, 2.0, 0.5, 0.1};
    layer.insert(s);
    // The first three share the cell [1, 1.5)^2.
    const double w1 = 1.0, w2 = 0.25, w3 = 4.0;
    const auto e = layer.estimateAt(V2(1.25, 1.25));
    ASSERT_TRUE(e.has_value());
    EXPECT_NEAR(e->mean, (w1 * 10 + w2 * 14 + w3 * 11) / (w1 + w2 + w3), 1e-12);
    EXPECT_NEAR(e->variance, 1.0 / (w1 + w2 + w3), 1e-12);
    EXPECT_EQ(e->count, 3u);
    EXPECT_NEAR(layer.estimateAt(V2(3.2, 0.4))->mean, -3.0, 1e-12);
    EXPECT_FALSE(layer.estimateAt(V2(0.2, 3.0)).has_value());
    EXPECT_EQ(layer.size(), 2u);

    // Values without stds take the default; order does not matter (information form).
    PropertyLayer a(opts(), kRef), b(opts(), kRef);
    a.fuse(V2(0.2, 0.2), 1.0, 2.0);
    a.fuse(V2(0.3, 0.2), 5.0, 1.0);
    b.fuse(V2(0.3, 0.2), 5.0, 1.0);
    RegionScan d;
    d.hits = {V2(0.2, 0.2)};
    d.hit_values = {1.0};
    b.insert(d);
    EXPECT_NEAR(a.estimateAt(V2(0.25, 0.25))->mean, b.estimateAt(V2(0.25, 0.25))->mean, 1e-15);
    EXPECT_NEAR(a.estimateAt(V2(0.25, 0.25))->mean, (0.25 * 1 + 1 * 5) / 1.25, 1e-15);
}

TEST(PropertyLayerTest, BadValuesAreRejectedWithoutPartialUpdates)
{
    PropertyLayer layer(opts(), kRef);
    RegionScan s;
    s.hits = {V2(1, 1), V2(2, 1)};
    s.hit_values = {1.0, std::numeric_limits<double>::quiet_NaN()};
    EXPECT_THROW(layer.insert(s), std::invalid_argument);
    EXPECT_EQ(layer.size(), 0u);
    s.hit_values = {1.0, 2.0};
    s.hit_value_stds = {1.0, 0.0};
    EXPECT_THROW(layer.insert(s), std::invalid_argument);
    s.hit_value_stds = {1.0, -1.0};
    EXPECT_THROW(layer.insert(s), std::invalid_argument);
    s.hit_value_stds = {1.0};
    EXPECT_THROW(layer.insert(s), std::invalid_argument);
    s.hit_values = {1.0};
    s.hit_value_stds.clear();
    EXPECT_THROW(layer.insert(s), std::invalid_argument);
    EXPECT_EQ(layer.size(), 0u);
    EXPECT_THROW(layer.fuse(V2(1, 1), 1.0, std::nan("")), std::invalid_argument);
    s.hit_values.clear();  // no values: nothing to fuse, not an error
    EXPECT_NO_THROW(layer.insert(s));
}

TEST(PropertyLayerTest, ScanPointsTakeIntensitiesFromMrptScans)
{
    mrpt::obs::CObservation2DRangeScan obs;
    obs.aperture = static_cast<float>(M_PI / 2);
    obs.rightToLeft = true;
    obs.resizeScan(3);
    for (size_t i = 0; i < 3; ++i)
    {
        obs.setScanRange(i, 2.0f + static_cast<float>(i));
        obs.setScanRangeValidity(i, i != 1);
    }
    EXPECT_TRUE(ScanPoints::fromRangeScan(obs).values.empty());
    obs.setScanHasIntensity(true);
    for (size_t i = 0; i < 3; ++i) obs.setScanIntensity(i, 100 + static_cast<int>(i));
    const ScanPoints sp = ScanPoints::fromRangeScan(obs, 0.05, 0.01);
    ASSERT_EQ(sp.points.size(), 2u);
    EXPECT_EQ(sp.values, (std::vector<double>{100.0, 102.0}));
    EXPECT_DOUBLE_EQ(sp.range_std_m, 0.05);
    EXPECT_THROW(ScanPoints::fromRangeScan(obs, -1.0), std::invalid_argument);

    ScanPoints bad = sp;
    bad.values.push_back(1.0);
    EXPECT_THROW(bad.validate(), std::invalid_argument);
    bad = sp;
    bad.value_stds = {1.0, std::nan("")};
    EXPECT_THROW(bad.validate(), std::invalid_argument);
}

TEST(PropertyLayerTest, RendersIntoHeightGridAndRoundTrips)
{
    PropertyLayer layer(opts(), kRef);
    layer.fuse(V2(1.2, 1.2), 3.0, 0.5);
    layer.fuse(V2(1.3, 1.1), 5.0, 0.5);
    // Region moved by (10, 0) since creation.
    const hymm::ltr::TriangleFrame ref(kRef[0], kRef[1], kRef[2]);
    const hymm::ltr::TriangleFrame cur(kRef[0] + V2(10, 0), kRef[1] + V2(10, 0), kRef[2] + V2(10, 0));
    const hymm::ltr::AffineRegionMap m(ref, cur);
    mrpt::maps::CHeightGridMap2D hg(mrpt::maps::CHeightGridMap2D::mrSimpleAverage, 9, 15, -1, 5, 0.1);
    layer.renderInto(m, hg);
    const auto* c = hg.cellByPos(11.25, 1.25);
    ASSERT_NE(c, nullptr);
    EXPECT_NEAR(c->h, 4.0, 1e-6);
    EXPECT_NEAR(c->var, std::sqrt(0.125), 1e-6);  // std of two 0.5-sigma values
    EXPECT_EQ(c->w, 2u);
    EXPECT_EQ(hg.cellByPos(12.25, 0.25)->w, 0u);

    ScalarField mean = ScalarField::covering(V2(9, -1), V2(15, 5), 0.1, std::nan(""));
    ScalarField sd = mean;
    layer.renderFields(m, mean, &sd);
    EXPECT_NEAR(mean.at(V2(11.25, 1.25)), 4.0, 1e-12);
    EXPECT_TRUE(std::isnan(mean.at(V2(12.25, 0.25))));

    std::stringstream ss;
    layer.save(ss);
    PropertyLayer copy(opts(), kRef);
    copy.load(ss);
    EXPECT_EQ(copy.estimateAt(V2(1.25, 1.25))->mean, layer.estimateAt(V2(1.25, 1.25))->mean);
    std::stringstream bad("property 1\n5 0x0p+0 0x1p+0 1\n");  // zero information
    EXPECT_THROW(copy.load(bad), std::runtime_error);
}

/** An MRPT scan of the wall test scene (synthetic_partition.h) whose intensities are
 *  the wall's property 80 + 0.5 y plus Gaussian noise of `sigma`, rounded as MRPT
 *  stores them. */
mrpt::obs::CObservation2DRangeScan noisyWallScan(std::mt19937& rng, double sigma)
{
    using namespace hymm::dense::synthetic;
    const ScanPoints geometry = wallScan(kVehicle, kMount, kWallX, kBeams, kHalfFov);
    const WorldScan world = geometry.toWorld(kVehicle, 100.0);
    mrpt::obs::CObservation2DRangeScan obs;
    obs.aperture = static_cast<float>(2 * kHalfFov);
    obs.rightToLeft = true;
    obs.maxRange = 80.0f;
    obs.sensorPose = mrpt::poses::CPose3D(kMount.x, kMount.y, 0, kMount.phi, 0, 0);
    obs.resizeScan(kBeams);
    obs.setScanHasIntensity(true);
    std::normal_distribution<double> noise(0.0, sigma);
    for (size_t i = 0; i < static_cast<size_t>(kBeams); ++i)
    {
        obs.setScanRange(i, static_cast<float>(geometry.points[i].norm()));
        obs.setScanRangeValidity(i, true);
        const double truth = 80.0 + 0.5 * world.beams[i].end.y();
        obs.setScanIntensity(i, static_cast<int>(std::lround(truth + noise(rng))));
    }
    return obs;
}

/** Cells of a rendered property field (non-NaN), with the truth at their centres. */
struct RenderedCells
{
    std::vector<double> z;       // (mean - truth) / stddev
    std::vector<double> stddev;  // by cell, row-major
};

RenderedCells renderWall(const HybridMetricMap& map, const hymm::ltr::RegionPartition& partition)
{
    ScalarField mean, sd;
    map.renderProperty(partition, 0.2, mean, sd);
    RenderedCells out;
    for (int iy = 0; iy < mean.sizeY(); ++iy)
        for (int ix = 0; ix < mean.sizeX(); ++ix)
        {
            if (std::isnan(mean.values(iy, ix))) continue;
            const V2 c = mean.cellCentre(ix, iy);
            EXPECT_NEAR(c.x(), synthetic::kWallX, 0.3);
            out.z.push_back((mean.values(iy, ix) - (80.0 + 0.5 * c.y())) / sd.values(iy, ix));
            out.stddev.push_back(sd.values(iy, ix));
        }
    return out;
}

TEST(PropertyLayerTest, NoisyIntensitiesAreRecoveredWithAnHonestShrinkingStd)
{
    // Intensity noise sigma 3 (plus the rounding to integers, variance 1/12), and the
    // layer told sigma 3: each cell's std is 3 / sqrt(values fused).
    constexpr double kSigma = 3.0;
    synthetic::WallWorld w;
    HybridMetricMap::Options o;
    o.enable_points = o.enable_occupancy = false;
    o.enable_property = true;
    o.property.cell_size_m = 0.2;
    o.property.default_value_std = kSigma;
    HybridMetricMap map(o);
    std::mt19937 rng(11);
    const auto insert = [&](int scans)
    {
        for (int k = 0; k < scans; ++k)
        {
            const ScanPoints pts = ScanPoints::fromRangeScan(noisyWallScan(rng, kSigma));
            ASSERT_EQ(pts.values.size(), static_cast<size_t>(synthetic::kBeams));
            map.insertScan(pts, synthetic::kVehicle, w.partition);
        }
    };
    insert(4);
    const RenderedCells few = renderWall(map, w.partition);
    insert(32);
    const RenderedCells many = renderWall(map, w.partition);

    // The same cells, each fusing 9 times as many values: a third of the std.
    ASSERT_EQ(few.stddev.size(), many.stddev.size());
    ASSERT_GT(many.stddev.size(), 30u);
    for (size_t i = 0; i < many.stddev.size(); ++i)
        EXPECT_NEAR(many.stddev[i], few.stddev[i] / 3, 1e-9);

    // Errors against the true property, in units of the stated std: zero mean, unit
    // RMS (sigma_eff / sigma = sqrt(1 + 1/(12 * 9)) = 1.005 from the rounding).
    for (const RenderedCells* r : {&few, &many})
    {
        double mean = 0, ms = 0;
        for (double z : r->z)
        {
            mean += z;
            ms += z * z;
        }
        const double n = static_cast<double>(r->z.size());
        mean /= n;
        EXPECT_NEAR(mean, 0.0, 4 / std::sqrt(n));
        EXPECT_NEAR(std::sqrt(ms / n), 1.0, 0.25);
    }
}

}  // namespace
