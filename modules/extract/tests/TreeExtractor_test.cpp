#include <gtest/gtest.h>
#include <hymm/extract/TreeExtractor.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "synthetic_scan.h"

#include <cmath>
#include <limits>

namespace
{
using hymm::extract::ScanFeature;
using hymm::extract::TreeExtractor;
using namespace hymm::extract::testing;

const Eigen::Vector3d kSensor(2.0, -1.0, 0.3);  // global pose of the laser

struct TreeSpec
{
    double range, bearing_deg, diameter;  // of the centre, sensor frame
};

World forest(const std::vector<TreeSpec>& trees)
{
    World w;
    for (const auto& t : trees)
        w.discs.push_back(
            {worldFromSensor(kSensor, t.range, t.bearing_deg * kDeg), t.diameter / 2.0});
    return w;
}

Eigen::Vector2d centreOf(const ScanFeature& f)
{
    return f.range * Eigen::Vector2d(std::cos(f.bearing), std::sin(f.bearing));
}

// The extracted feature closest to the expected centre, and its centre error.
const ScanFeature* nearest(
    const std::vector<ScanFeature>& found, const TreeSpec& t, double* err)
{
    const Eigen::Vector2d c = t.range * Eigen::Vector2d(std::cos(t.bearing_deg * kDeg),
                                                        std::sin(t.bearing_deg * kDeg));
    const ScanFeature* best = nullptr;
    *err = std::numeric_limits<double>::infinity();
    for (const auto& f : found)
    {
        const double e = (centreOf(f) - c).norm();
        if (e < *err) *err = e, best = &f;
    }
    return best;
}

const std::vector<TreeSpec> kTrees = {
    {5.0, -40.0, 0.4}, {8.0, 0.0, 0.6}, {4.0, 35.0, 0.3}, {12.0, 60.0, 0.8}};

TEST(TreeExtractorTest, NoiseFreeTrunksAreRecoveredWithinOneCentimetre)
{
    const auto scan = castScan(forest(kTrees), kSensor, Laser{});
    const TreeExtractor ex{TreeExtractor::Options{}};
    const auto res = ex.extract(scan);
    ASSERT_EQ(res.trees.size(), kTrees.size());
    for (const auto& t : kTrees)
    {
        double err = 0;
        const ScanFeature* f = nearest(res.trees, t, &err);
        ASSERT_NE(f, nullptr);
        EXPECT_LT(err, 0.01) << "tree at " << t.range << " m, " << t.bearing_deg << " deg";
        EXPECT_NEAR(f->diameter, t.diameter, 0.01);
        EXPECT_FALSE(f->used_fallback);
        // Range to the centre, not to the surface.
        EXPECT_NEAR(f->range, t.range, 0.01);
        EXPECT_LT(f->fit_rms, 1e-3);
    }
    // Beams that hit nothing are flagged invalid by the sensor and counted as skipped.
    EXPECT_EQ(res.beams.used + res.skipped_invalid, scan.getScanSize());
    EXPECT_EQ(res.beams.invalid, res.skipped_invalid);
}

TEST(TreeExtractorTest, NoisyTrunksAreRecoveredWithinAFewCentimetres)
{
    TreeExtractor::Options o;
    o.max_fit_rms = 0.05;
    const TreeExtractor ex(o);
    double sum_err = 0, sum_derr = 0;
    size_t n = 0;
    for (unsigned seed = 1; seed <= 10; ++seed)
    {
        Laser laser;
        laser.range_noise = 0.01;
        laser.seed = seed;
        const auto res = ex.extract(castScan(forest(kTrees), kSensor, laser));
        EXPECT_EQ(res.trees.size(), kTrees.size()) << "seed " << seed;
        for (const auto& t : kTrees)
        {
            double err = 0;
            const ScanFeature* f = nearest(res.trees, t, &err);
            if (!f) continue;
            EXPECT_LT(err, 0.10) << "seed " << seed << " tree at " << t.range << " m";
            EXPECT_NEAR(f->diameter, t.diameter, 0.2) << "seed " << seed;
            sum_err += err;
            sum_derr += std::abs(f->diameter - t.diameter);
            ++n;
        }
    }
    ASSERT_GT(n, 0u);
    EXPECT_LT(sum_err / n, 0.04);
    EXPECT_LT(sum_derr / n, 0.08);
}

TEST(TreeExtractorTest, PartlyOccludedTrunkIsRejected)
{
    // The far trunk is half hidden behind the near one: its visible arc is cut by an
    // occluding edge, so its width (and centre) would be wrong.
    const std::vector<TreeSpec> trees = {{4.0, 10.0, 0.4}, {8.0, 14.0, 1.0}};
    const auto scan = castScan(forest(trees), kSensor, Laser{});
    const TreeExtractor ex{TreeExtractor::Options{}};
    const auto res = ex.extract(scan);
    ASSERT_EQ(res.trees.size(), 1u);
    double err = 0;
    nearest(res.trees, trees[0], &err);
    EXPECT_LT(err, 0.01);
    EXPECT_EQ(res.rejected.occluded, 1u);

    // The rejection is the occlusion check's doing: without it both clusters pass.
    TreeExtractor::Options o;
    o.reject_occluded = false;
    const auto all = TreeExtractor(o).extract(scan);
    EXPECT_EQ(all.rejected.occluded, 0u);
    EXPECT_EQ(all.trees.size(), 2u);
}

TEST(TreeExtractorTest, WallsAreRejected)
{
    World w;
    // A 4 m wall 6 m ahead, a 10 m wall 15 m to the left, and one tree to keep honest.
    w.walls.push_back({worldFromSensor(kSensor, 6.0, -20 * kDeg), worldFromSensor(kSensor, 6.5, 15 * kDeg)});
    w.walls.push_back({worldFromSensor(kSensor, 15.0, 50 * kDeg), worldFromSensor(kSensor, 16.0, 85 * kDeg)});
    w.discs.push_back({worldFromSensor(kSensor, 5.0, -60 * kDeg), 0.25});
    for (double noise : {0.0, 0.01})
    {
        Laser laser;
        laser.range_noise = noise;
        const auto res = TreeExtractor(TreeExtractor::Options{}).extract(castScan(w, kSensor, laser));
        ASSERT_EQ(res.trees.size(), 1u) << "noise " << noise;
        double err = 0;
        nearest(res.trees, TreeSpec{5.0, -60.0, 0.5}, &err);
        EXPECT_LT(err, 0.05);
        EXPECT_EQ(res.rejected.too_large + res.rejected.bad_fit, 2u) << "noise " << noise;
    }
}

TEST(TreeExtractorTest, NanNegativeAndInvalidBeamsAreSkippedAndCounted)
{
    auto scan = castScan(forest(kTrees), kSensor, Laser{});
    // Corrupt beams far from any trunk (the trunks sit at -40, 0, 35, 60 deg; beam i is at
    // -90 + i/2 deg).
    const std::vector<size_t> nan_beams = {10, 11, 290};
    const std::vector<size_t> neg_beams = {20, 350};
    const std::vector<size_t> close_beams = {30};  // below min_range
    for (size_t i : nan_beams)
    {
        scan.setScanRange(i, std::numeric_limits<float>::quiet_NaN());
        scan.setScanRangeValidity(i, true);
    }
    for (size_t i : neg_beams)
    {
        scan.setScanRange(i, -1.0f);
        scan.setScanRangeValidity(i, true);
    }
    for (size_t i : close_beams)
    {
        scan.setScanRange(i, 0.05f);
        scan.setScanRangeValidity(i, true);
    }
    size_t invalid = 0;
    for (size_t i = 0; i < scan.getScanSize(); ++i)
        if (!scan.getScanRangeValidity(i)) ++invalid;

    const auto res = TreeExtractor(TreeExtractor::Options{}).extract(scan);
    EXPECT_EQ(res.beams.not_finite, nan_beams.size());
    EXPECT_EQ(res.beams.out_of_range, neg_beams.size() + close_beams.size());
    EXPECT_EQ(res.beams.invalid, invalid);
    EXPECT_EQ(res.skipped_invalid, invalid + nan_beams.size() + neg_beams.size() + close_beams.size());
    EXPECT_EQ(res.beams.used + res.skipped_invalid, res.beams.total);
    EXPECT_EQ(res.trees.size(), kTrees.size());
    for (const auto& f : res.trees)
    {
        EXPECT_TRUE(std::isfinite(f.range));
        EXPECT_TRUE(std::isfinite(f.bearing));
    }
}

TEST(TreeExtractorTest, BeamsBeyondMaxRangeAreSkipped)
{
    TreeExtractor::Options o;
    o.max_range = 10.0;  // the trunk at 12 m lies beyond it
    const auto res = TreeExtractor(o).extract(castScan(forest(kTrees), kSensor, Laser{}));
    EXPECT_EQ(res.trees.size(), kTrees.size() - 1);
    EXPECT_GT(res.beams.out_of_range, 0u);
}

TEST(TreeExtractorTest, FewBeamTrunksUseTheAngularWidthFallback)
{
    // 0.3 m at 10 m with 0.5 deg beams: 3-4 beams, too few for a 3-parameter fit.
    const std::vector<TreeSpec> trees = {{10.0, 20.0, 0.3}};
    const auto res =
        TreeExtractor(TreeExtractor::Options{}).extract(castScan(forest(trees), kSensor, Laser{}));
    ASSERT_EQ(res.trees.size(), 1u);
    const auto& f = res.trees[0];
    EXPECT_TRUE(f.used_fallback);
    EXPECT_NEAR(f.range, 10.0, 0.1);
    EXPECT_NEAR(f.bearing, 20.0 * kDeg, 0.5 * kDeg);
    EXPECT_NEAR(f.diameter, 0.3, 0.1);
}

TEST(TreeExtractorTest, ClustersCutByTheFieldOfViewAreRejected)
{
    // A trunk straddling the first beam (bearing -90 deg).
    const std::vector<TreeSpec> trees = {{5.0, -90.0, 0.6}, {5.0, 0.0, 0.4}};
    const auto scan = castScan(forest(trees), kSensor, Laser{});
    const auto res = TreeExtractor(TreeExtractor::Options{}).extract(scan);
    EXPECT_EQ(res.trees.size(), 1u);
    EXPECT_EQ(res.rejected.scan_edge, 1u);
}

TEST(TreeExtractorTest, ObservationCarriesSensorPoseAndNoise)
{
    const mrpt::poses::CPose3D mounting(0.5, 0.1, 1.2, 0.05, 0, 0);
    auto scan = castScan(forest(kTrees), kSensor, Laser{}, mounting);
    scan.timestamp = mrpt::Clock::fromDouble(123.5);
    TreeExtractor::Options o;
    o.std_range = 0.07;
    o.std_bearing = 0.9 * kDeg;
    const TreeExtractor ex(o);
    const auto obs = ex.extractObservation(scan);
    const auto res = ex.extract(scan);
    ASSERT_EQ(obs.sensedData.size(), res.trees.size());
    EXPECT_EQ(obs.sensorLocationOnRobot, mounting);
    EXPECT_EQ(obs.timestamp, scan.timestamp);
    EXPECT_EQ(obs.sensorLabel, "LASER");
    EXPECT_FLOAT_EQ(obs.sensor_std_range, 0.07f);
    EXPECT_FLOAT_EQ(obs.sensor_std_yaw, static_cast<float>(0.9 * kDeg));
    EXPECT_FALSE(obs.validCovariances);
    for (size_t i = 0; i < obs.sensedData.size(); ++i)
    {
        EXPECT_EQ(obs.sensedData[i].landmarkID, -1);
        EXPECT_NEAR(obs.sensedData[i].range, res.trees[i].range, 1e-5);
        EXPECT_NEAR(obs.sensedData[i].yaw, res.trees[i].bearing, 1e-6);
        EXPECT_EQ(obs.sensedData[i].pitch, 0.0f);
    }
}

TEST(TreeExtractorTest, OptionsLoadStrictlyAndRoundTrip)
{
    mrpt::config::CConfigFileMemory cfg(
        "[TreeExtractor]\nmin_diameter = 0.1\nmax_diameter = 2\nstd_bearing_deg = 1\n"
        "reject_occluded = false\n");
    TreeExtractor::Options o;
    o.loadFromConfigFile(cfg, "TreeExtractor");
    EXPECT_DOUBLE_EQ(o.min_diameter, 0.1);
    EXPECT_DOUBLE_EQ(o.max_diameter, 2.0);
    EXPECT_NEAR(o.std_bearing, kDeg, 1e-12);
    EXPECT_FALSE(o.reject_occluded);

    mrpt::config::CConfigFileMemory saved;
    o.saveToConfigFile(saved, "T");
    TreeExtractor::Options back;
    back.loadFromConfigFile(saved, "T");
    EXPECT_DOUBLE_EQ(back.min_diameter, o.min_diameter);
    EXPECT_NEAR(back.std_bearing, o.std_bearing, 1e-12);
    EXPECT_EQ(back.reject_occluded, o.reject_occluded);
    EXPECT_EQ(back.fit_min_points, o.fit_min_points);
}

TEST(TreeExtractorTest, BadOptionsAreClearErrors)
{
    TreeExtractor::Options o;
    mrpt::config::CConfigFileMemory neg("[TreeExtractor]\nmin_diameter = -0.2\n");
    try
    {
        o.loadFromConfigFile(neg, "TreeExtractor");
        FAIL() << "no exception";
    }
    catch (const std::invalid_argument& e)
    {
        EXPECT_NE(std::string(e.what()).find("[TreeExtractor] min_diameter"), std::string::npos)
            << e.what();
    }
    mrpt::config::CConfigFileMemory typo("[TreeExtractor]\nmax_diametr = 1\n");
    EXPECT_THROW(TreeExtractor::Options().loadFromConfigFile(typo, "TreeExtractor"),
                 std::invalid_argument);
    mrpt::config::CConfigFileMemory inverted("[TreeExtractor]\nmin_diameter = 1\nmax_diameter = 0.5\n");
    EXPECT_THROW(TreeExtractor::Options().loadFromConfigFile(inverted, "TreeExtractor"),
                 std::invalid_argument);

    TreeExtractor::Options direct;
    direct.min_diameter = -1;
    EXPECT_THROW(TreeExtractor{direct}, std::invalid_argument);
    direct = TreeExtractor::Options{};
    direct.fit_min_points = 2;
    EXPECT_THROW(TreeExtractor{direct}, std::invalid_argument);
}

}  // namespace
