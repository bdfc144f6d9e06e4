#include <gtest/gtest.h>
#include <hymm/extract/ReflectorExtractor.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "synthetic_scan.h"

#include <cmath>
#include <limits>

namespace
{
using hymm::extract::ReflectorExtractor;
using hymm::extract::ScanFeature;
using namespace hymm::extract::testing;

const Eigen::Vector3d kSensor(-3.0, 4.0, -1.2);
constexpr int kBright = 1000, kDull = 60;

Eigen::Vector2d centreOf(const ScanFeature& f)
{
    return f.range * Eigen::Vector2d(std::cos(f.bearing), std::sin(f.bearing));
}

double nearestError(const std::vector<ScanFeature>& found, const Eigen::Vector2d& c_sensor)
{
    double best = std::numeric_limits<double>::infinity();
    for (const auto& f : found) best = std::min(best, (centreOf(f) - c_sensor).norm());
    return best;
}

// Two cylindrical beacons and a dull tree in front of a dull wall.
World beaconWorld(double radius)
{
    World w;
    // Perpendicular to the sensor axis, 12 m ahead; its ends lie beyond the 30 m max range.
    w.walls.push_back({worldFromSensor(kSensor, 12.0 / std::cos(75 * kDeg), -75 * kDeg),
                       worldFromSensor(kSensor, 12.0 / std::cos(75 * kDeg), 75 * kDeg), kDull});
    w.discs.push_back({worldFromSensor(kSensor, 4.0, -30 * kDeg), radius, kBright});
    w.discs.push_back({worldFromSensor(kSensor, 7.0, 20 * kDeg), radius, kBright});
    w.discs.push_back({worldFromSensor(kSensor, 5.0, 50 * kDeg), 0.3, kDull});
    return w;
}

Laser intensityLaser()
{
    Laser l;
    l.beams = 721;  // 0.25 deg
    l.intensity = true;
    return l;
}

TEST(ReflectorExtractorTest, CylindricalBeaconCentresAreFound)
{
    const double radius = 0.05;
    const auto scan = castScan(beaconWorld(radius), kSensor, intensityLaser());
    ReflectorExtractor::Options o;
    o.beacon_radius = radius;
    const auto res = ReflectorExtractor(o).extract(scan);
    ASSERT_EQ(res.reflectors.size(), 2u);
    EXPECT_LT(nearestError(res.reflectors, {4.0 * std::cos(-30 * kDeg), 4.0 * std::sin(-30 * kDeg)}), 0.03);
    EXPECT_LT(nearestError(res.reflectors, {7.0 * std::cos(20 * kDeg), 7.0 * std::sin(20 * kDeg)}), 0.03);
    for (const auto& f : res.reflectors) EXPECT_DOUBLE_EQ(f.diameter, 2 * radius);

    // Without the radius the centre sits on the visible surface: about one radius short.
    const auto flat = ReflectorExtractor(ReflectorExtractor::Options{}).extract(scan);
    ASSERT_EQ(flat.reflectors.size(), 2u);
    for (size_t i = 0; i < 2; ++i)
        EXPECT_NEAR(res.reflectors[i].range - flat.reflectors[i].range, radius, 1e-9);
}

TEST(ReflectorExtractorTest, FlatTapeCentreIsTheMeanOfItsPoints)
{
    World w;
    const Eigen::Vector2d a = worldFromSensor(kSensor, 6.0, -5 * kDeg);
    const Eigen::Vector2d b = worldFromSensor(kSensor, 6.0, 5 * kDeg);
    const Eigen::Vector2d dir = (b - a).normalized();
    // Dull wall with a 20 cm strip of tape in its middle.
    const Eigen::Vector2d mid = 0.5 * (a + b);
    w.walls.push_back({a, mid - 0.1 * dir, kDull});
    w.walls.push_back({mid - 0.1 * dir, mid + 0.1 * dir, kBright});
    w.walls.push_back({mid + 0.1 * dir, b, kDull});
    const auto res =
        ReflectorExtractor(ReflectorExtractor::Options{}).extract(castScan(w, kSensor, intensityLaser()));
    ASSERT_EQ(res.reflectors.size(), 1u);
    EXPECT_LT((centreOf(res.reflectors[0]) - sensorFromWorld(kSensor, mid)).norm(), 0.02);
}

TEST(ReflectorExtractorTest, WideBrightClustersAndSmallOnesAreRejected)
{
    World w = beaconWorld(0.05);
    // A shiny 2 m panel.
    w.walls.push_back({worldFromSensor(kSensor, 5.0, -70 * kDeg),
                       worldFromSensor(kSensor, 5.0, -50 * kDeg), kBright});
    const auto scan = castScan(w, kSensor, intensityLaser());
    const auto res = ReflectorExtractor(ReflectorExtractor::Options{}).extract(scan);
    EXPECT_EQ(res.reflectors.size(), 2u);
    EXPECT_EQ(res.rejected_too_wide, 1u);

    ReflectorExtractor::Options o;
    o.min_points = 50;
    const auto strict = ReflectorExtractor(o).extract(scan);
    EXPECT_EQ(strict.reflectors.size(), 0u);
    EXPECT_EQ(strict.rejected_too_few_points, 2u);
}

TEST(ReflectorExtractorTest, InvalidBeamsAreSkippedAndCounted)
{
    auto scan = castScan(beaconWorld(0.05), kSensor, intensityLaser());
    size_t no_return = 0;
    for (size_t i = 0; i < scan.getScanSize(); ++i)
        if (!scan.getScanRangeValidity(i)) ++no_return;
    ASSERT_TRUE(scan.getScanRangeValidity(360));  // the wall straight ahead
    scan.setScanRange(358, std::numeric_limits<float>::quiet_NaN());
    scan.setScanRange(359, -2.0f);
    scan.setScanRangeValidity(360, false);
    const auto res = ReflectorExtractor(ReflectorExtractor::Options{}).extract(scan);
    EXPECT_EQ(res.beams.not_finite, 1u);
    EXPECT_EQ(res.beams.out_of_range, 1u);
    EXPECT_EQ(res.beams.invalid, no_return + 1);
    EXPECT_EQ(res.skipped_invalid, no_return + 3);
    EXPECT_EQ(res.beams.used + res.skipped_invalid, scan.getScanSize());
    EXPECT_EQ(res.reflectors.size(), 2u);
}

TEST(ReflectorExtractorTest, ScanWithoutIntensityIsAnError)
{
    const auto scan = castScan(beaconWorld(0.05), kSensor, Laser{});
    EXPECT_THROW(ReflectorExtractor(ReflectorExtractor::Options{}).extract(scan),
                 std::invalid_argument);
}

TEST(ReflectorExtractorTest, ObservationIsInTheSensorFrame)
{
    const mrpt::poses::CPose3D mounting(1.0, 0.0, 0.5, 0.2, 0, 0);
    const auto scan = castScan(beaconWorld(0.05), kSensor, intensityLaser(), mounting);
    const ReflectorExtractor ex{ReflectorExtractor::Options{}};
    const auto obs = ex.extractObservation(scan);
    ASSERT_EQ(obs.sensedData.size(), 2u);
    EXPECT_EQ(obs.sensorLocationOnRobot, mounting);
    for (const auto& m : obs.sensedData) EXPECT_EQ(m.landmarkID, -1);
}

TEST(ReflectorExtractorTest, BadOptionsAreClearErrors)
{
    mrpt::config::CConfigFileMemory cfg("[ReflectorExtractor]\nbeacon_radius = -0.1\n");
    try
    {
        ReflectorExtractor::Options().loadFromConfigFile(cfg, "ReflectorExtractor");
        FAIL() << "no exception";
    }
    catch (const std::invalid_argument& e)
    {
        EXPECT_NE(std::string(e.what()).find("[ReflectorExtractor] beacon_radius"), std::string::npos)
            << e.what();
    }
    mrpt::config::CConfigFileMemory typo("[ReflectorExtractor]\nmin_intesity = 3\n");
    EXPECT_THROW(ReflectorExtractor::Options().loadFromConfigFile(typo, "ReflectorExtractor"),
                 std::invalid_argument);
    mrpt::config::CConfigFileMemory ok("[ReflectorExtractor]\nmin_intensity = 500\nbeacon_radius = 0.04\n");
    ReflectorExtractor::Options o;
    o.loadFromConfigFile(ok, "ReflectorExtractor");
    EXPECT_EQ(o.min_intensity, 500);
    EXPECT_DOUBLE_EQ(o.beacon_radius, 0.04);
}

}  // namespace
