/**
 * @file ScanPoints_test.cpp
 * @brief Beams with no return: ScanPoints::fromRangeScan keeps their bearings and counts
 *        failed readings apart, toWorld makes them free beams cut at the configured
 *        range, the occupancy layer frees cells along them with the model of the
 *        beyond-range beams, and with the option off (default) every layer is exactly
 *        what it was without them.
 */
#include "hymm/dense/HybridMetricMap.h"
#include "hymm/dense/ScanPoints.h"

#include "synthetic_partition.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace
{
using namespace hymm::dense;
using namespace hymm::dense::synthetic;
using V2 = Eigen::Vector2d;

/** 181 beams over 180 deg, every 5th with no return (flagged invalid, range = max range,
 *  as LaserSimulator writes it), beams 11, 12, 13, 14 valid but NaN, -1, 0 and +inf;
 *  the others return at 3 + 0.01 i m with intensity i. Sensor mounted 0.5 m ahead,
 *  turned 0.1 rad. */
mrpt::obs::CObservation2DRangeScan mixedScan()
{
    mrpt::obs::CObservation2DRangeScan obs;
    obs.aperture = static_cast<float>(M_PI);
    obs.rightToLeft = true;
    obs.maxRange = 40.0f;
    obs.sensorPose = mrpt::poses::CPose3D(0.5, 0, 0, 0.1, 0, 0);
    obs.resizeScan(181);
    obs.setScanHasIntensity(true);
    for (size_t i = 0; i < 181; ++i)
    {
        const bool no_return = i % 5 == 0;
        obs.setScanRange(i, no_return ? 40.0f : static_cast<float>(3.0 + 0.01 * static_cast<double>(i)));
        obs.setScanRangeValidity(i, !no_return);
        obs.setScanIntensity(i, static_cast<int>(i));
    }
    obs.setScanRange(11, std::numeric_limits<float>::quiet_NaN());
    obs.setScanRange(12, -1.0f);
    obs.setScanRange(13, 0.0f);
    obs.setScanRange(14, std::numeric_limits<float>::infinity());
    return obs;
}

TEST(ScanPointsTest, FromRangeScanKeepsNoReturnBearingsAndCountsFailedReadingsApart)
{
    const auto obs = mixedScan();
    const ScanPoints s = ScanPoints::fromRangeScan(obs);
    EXPECT_NEAR(s.sensor_on_vehicle.x, 0.5, 1e-12);
    EXPECT_NEAR(s.sensor_on_vehicle.phi, 0.1, 1e-12);
    ASSERT_EQ(s.no_return_bearings.size(), 37u);  // i = 0, 5, ..., 180
    for (size_t k = 0; k < s.no_return_bearings.size(); ++k)
        EXPECT_DOUBLE_EQ(s.no_return_bearings[k], obs.getScanAngle(5 * k));
    EXPECT_EQ(s.skipped, 4u);  // NaN, -1, 0, +inf: failed readings, not free space
    ASSERT_EQ(s.points.size(), 181u - 37u - 4u);
    ASSERT_EQ(s.values.size(), s.points.size());
    // Every kept return is a valid, finite, positive reading, in order, with its value.
    size_t k = 0;
    for (size_t i = 0; i < 181; ++i)
    {
        if (i % 5 == 0 || (i >= 11 && i <= 14)) continue;
        const double r = static_cast<double>(obs.getScanRange(i)), a = obs.getScanAngle(i);
        EXPECT_EQ(s.points[k], V2(r * std::cos(a), r * std::sin(a))) << i;  // bit for bit
        EXPECT_EQ(s.rangeBearing(k), V2(r, a)) << i;  // the raw measurement, not re-derived
        EXPECT_EQ(s.values[k], static_cast<double>(i));
        ++k;
    }
    EXPECT_EQ(k, s.points.size());
    // Without the raw measurement, the polar form of the point; a wrong size is an error.
    ScanPoints cartesian = s;
    cartesian.range_bearing.clear();
    EXPECT_NEAR((cartesian.rangeBearing(3) - s.rangeBearing(3)).norm(), 0.0, 1e-12);
    cartesian.range_bearing.resize(2);
    EXPECT_THROW(cartesian.validate(), std::invalid_argument);
}

TEST(ScanPointsTest, ToWorldMakesNoReturnBeamsFreeUpToTheirRange)
{
    const ScanPoints s = ScanPoints::fromRangeScan(mixedScan());
    const mrpt::math::TPose2D vehicle{2.0, -1.0, 0.3};
    const mrpt::math::TPose2D sensor = vehicle + s.sensor_on_vehicle;

    // Off (the default): exactly the beams of the same scan without no-return bearings.
    ScanPoints bare = s;
    bare.no_return_bearings.clear();
    const WorldScan off = s.toWorld(vehicle, 25.0);
    const WorldScan ref = bare.toWorld(vehicle, 25.0, 10.0);
    EXPECT_EQ(off.no_return, 0u);
    ASSERT_EQ(off.beams.size(), s.points.size());
    ASSERT_EQ(ref.beams.size(), off.beams.size());
    for (size_t i = 0; i < off.beams.size(); ++i)
    {
        EXPECT_EQ(off.beams[i].end, ref.beams[i].end);
        EXPECT_TRUE(off.beams[i].hit);
        EXPECT_FALSE(off.beams[i].no_return);
    }
    EXPECT_EQ(off.lo, ref.lo);
    EXPECT_EQ(off.hi, ref.hi);

    // On: one free beam per bearing, after the returns, cut at min(range, max range).
    for (const double range : {10.0, 40.0})
    {
        const WorldScan on = s.toWorld(vehicle, 25.0, range);
        const double cut = std::min(range, 25.0);
        ASSERT_EQ(on.no_return, s.no_return_bearings.size());
        ASSERT_EQ(on.beams.size(), s.points.size() + s.no_return_bearings.size());
        EXPECT_EQ(on.beyond_range, 0u);
        for (size_t i = 0; i < s.points.size(); ++i) EXPECT_EQ(on.beams[i].end, off.beams[i].end);
        for (size_t k = 0; k < s.no_return_bearings.size(); ++k)
        {
            const WorldBeam& b = on.beams[s.points.size() + k];
            EXPECT_FALSE(b.hit);
            EXPECT_TRUE(b.no_return);
            EXPECT_EQ(b.source, k);
            const double a = sensor.phi + s.no_return_bearings[k];
            EXPECT_NEAR((b.end - V2(sensor.x, sensor.y)).norm(), cut, 1e-9);
            EXPECT_NEAR(b.end.x(), sensor.x + cut * std::cos(a), 1e-9);
            EXPECT_NEAR(b.end.y(), sensor.y + cut * std::sin(a), 1e-9);
            EXPECT_TRUE((b.end.array() >= on.lo.array() && b.end.array() <= on.hi.array()).all());
        }
    }

    EXPECT_THROW(s.toWorld(vehicle, 25.0, -1.0), std::invalid_argument);
    EXPECT_THROW(s.toWorld(vehicle, 25.0, std::nan("")), std::invalid_argument);
    ScanPoints bad = s;
    bad.no_return_bearings.push_back(std::nan(""));
    EXPECT_THROW(bad.validate(), std::invalid_argument);
}

/** The wall scene of synthetic_partition.h with the beams of [-10, 10] deg (sensor
 *  frame) returning nothing: they pass through a doorway in the wall. */
ScanPoints wallWithDoorway()
{
    const ScanPoints wall = wallScan(kVehicle, kMount, kWallX, kBeams, kHalfFov);
    ScanPoints s;
    s.sensor_on_vehicle = wall.sensor_on_vehicle;
    for (const V2& p : wall.points)
    {
        const double a = std::atan2(p.y(), p.x());
        if (std::abs(a) <= 10.0 * M_PI / 180)
            s.no_return_bearings.push_back(a);
        else
            s.points.push_back(p);
    }
    return s;
}

HybridMetricMap::Options allLayers(double no_return_free_range_m)
{
    HybridMetricMap::Options o;
    o.enable_particles = o.enable_sog = true;
    o.occupancy.cell_size_m = 0.1;
    o.no_return_free_range_m = no_return_free_range_m;
    return o;
}

std::string saved(const HybridMetricMap& m)
{
    std::ostringstream ss;
    m.save(ss);
    return ss.str();
}

TEST(ScanPointsTest, OptionOffLeavesEveryLayerAsWithoutNoReturnBeams)
{
    WallWorld w;
    const ScanPoints s = wallWithDoorway();
    ASSERT_GT(s.no_return_bearings.size(), 30u);
    ScanPoints bare = s;
    bare.no_return_bearings.clear();
    HybridMetricMap with(allLayers(0.0)), without(allLayers(0.0));
    for (int k = 0; k < 3; ++k)
    {
        const auto a = with.insertScan(s, kVehicle, w.partition);
        const auto b = without.insertScan(bare, kVehicle, w.partition);
        EXPECT_EQ(a.beams, b.beams);
        EXPECT_EQ(a.no_return, 0u);
        EXPECT_EQ(a.returns_stored, b.returns_stored);
        EXPECT_EQ(a.regions_updated, b.regions_updated);
    }
    EXPECT_EQ(saved(with), saved(without));  // points, occupancy, particles, SOG: bit for bit
}

TEST(ScanPointsTest, OccupancyFreesCellsAlongNoReturnBeamsUpToTheirRange)
{
    WallWorld w;
    const ScanPoints s = wallWithDoorway();
    constexpr double kFree = 8.0;  // the doorway at 13.7 m lies beyond
    HybridMetricMap off(allLayers(0.0)), on(allLayers(kFree));
    HybridMetricMap::InsertStats st, st_off;
    for (int k = 0; k < 3; ++k)
    {
        st_off = off.insertScan(s, kVehicle, w.partition);
        st = on.insertScan(s, kVehicle, w.partition);
    }
    EXPECT_EQ(st.no_return, s.no_return_bearings.size());
    EXPECT_EQ(st.beams, s.points.size() + s.no_return_bearings.size());
    // The no-return beams are free space only: the return counts do not change.
    EXPECT_EQ(st.returns_stored, st_off.returns_stored);
    EXPECT_EQ(st.returns_outside, st_off.returns_outside);
    EXPECT_EQ(st.beyond_range, st_off.beyond_range);
    EXPECT_EQ(st.returns_stored + st.returns_outside, s.points.size());
    mrpt::maps::COccupancyGridMap2D og_off, og_on;
    off.renderOccupancy(w.partition, 0.1, og_off);
    on.renderOccupancy(w.partition, 0.1, og_on);

    // Sample along the middle of the doorway's beams, away from the returning beams.
    const V2 sensor(kVehicle.x + kMount.x, kVehicle.y);
    size_t near_free = 0, near_n = 0, far_unknown = 0, far_n = 0, off_unknown = 0, off_n = 0;
    for (double deg = -6; deg <= 6; deg += 1)
        for (double r = 0.5; r < 13.0; r += 0.25)
        {
            if (std::abs(r - kFree) < 0.3) continue;  // the cell at the cut
            const V2 p = sensor + r * V2(std::cos(deg * M_PI / 180), std::sin(deg * M_PI / 180));
            const float p_on = og_on.getPos(static_cast<float>(p.x()), static_cast<float>(p.y()));
            const float p_off = og_off.getPos(static_cast<float>(p.x()), static_cast<float>(p.y()));
            // (near the sensor the returning beams cross the same cells)
            if (r > 3)
            {
                ++off_n;
                off_unknown += std::abs(p_off - 0.5f) < 1e-3f;
            }
            if (r < kFree)
            {
                ++near_n;
                near_free += p_on < 0.3f;
            }
            else
            {
                ++far_n;
                far_unknown += std::abs(p_on - 0.5f) < 1e-3f;
            }
        }
    ASSERT_GT(near_n, 300u);
    ASSERT_GT(far_n, 200u);
    EXPECT_EQ(near_free, near_n);          // free up to the range
    EXPECT_EQ(far_unknown, far_n);         // unknown past it
    EXPECT_EQ(off_unknown, off_n);  // off: the doorway is never observed

    // Same inverse model as returns beyond max range: the no-return beams give exactly
    // the grid of beams whose returns lie beyond a max range equal to the free range.
    ScanPoints only_no_return, beyond;
    only_no_return.sensor_on_vehicle = beyond.sensor_on_vehicle = s.sensor_on_vehicle;
    only_no_return.no_return_bearings = s.no_return_bearings;
    for (const double a : s.no_return_bearings)
        beyond.points.push_back(2 * kFree * V2(std::cos(a), std::sin(a)));
    HybridMetricMap::Options o_a = allLayers(kFree), o_b = allLayers(0.0);
    o_a.enable_points = o_a.enable_particles = o_a.enable_sog = false;
    o_b.enable_points = o_b.enable_particles = o_b.enable_sog = false;
    o_b.max_range_m = kFree;
    HybridMetricMap a(o_a), b(o_b);
    const auto st_a = a.insertScan(only_no_return, kVehicle, w.partition);
    const auto st_b = b.insertScan(beyond, kVehicle, w.partition);
    EXPECT_EQ(st_a.no_return, st_b.beyond_range);
    mrpt::maps::COccupancyGridMap2D ga, gb;
    a.renderOccupancy(w.partition, 0.1, ga);
    b.renderOccupancy(w.partition, 0.1, gb);
    ASSERT_EQ(ga.getSizeX(), gb.getSizeX());
    ASSERT_EQ(ga.getSizeY(), gb.getSizeY());
    size_t free_cells = 0;
    for (unsigned y = 0; y < ga.getSizeY(); ++y)
        for (unsigned x = 0; x < ga.getSizeX(); ++x)
        {
            const float pa = ga.getCell(static_cast<int>(x), static_cast<int>(y));
            EXPECT_NEAR(pa, gb.getCell(static_cast<int>(x), static_cast<int>(y)), 1e-6f);
            free_cells += pa < 0.5f;
        }
    EXPECT_GT(free_cells, 300u);
}

TEST(ScanPointsTest, NoReturnRangeIsConfiguredStrictly)
{
    mrpt::config::CConfigFileMemory good("[HybridMetricMap]\nno_return_free_range_m=12\n");
    HybridMetricMap::Options o;
    EXPECT_DOUBLE_EQ(o.no_return_free_range_m, 0.0);  // off by default
    o.loadAll(good);
    EXPECT_DOUBLE_EQ(o.no_return_free_range_m, 12.0);
    mrpt::config::CConfigFileMemory saved_cfg;
    o.saveAll(saved_cfg);
    HybridMetricMap::Options back;
    back.loadAll(saved_cfg);
    EXPECT_DOUBLE_EQ(back.no_return_free_range_m, 12.0);
    for (const char* bad : {"-1", "nan", "far"})
    {
        mrpt::config::CConfigFileMemory cfg(std::string("[HybridMetricMap]\nno_return_free_range_m=") + bad + "\n");
        HybridMetricMap::Options x;
        EXPECT_THROW(x.loadAll(cfg), std::exception) << bad;
    }
    mrpt::config::CConfigFileMemory prot("[ParticlesLayer]\nfree_space_protection=false\n");
    HybridMetricMap::Options p;
    EXPECT_TRUE(p.particles.free_space_protection);
    p.loadAll(prot);
    EXPECT_FALSE(p.particles.free_space_protection);
}

}  // namespace
