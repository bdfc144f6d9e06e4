/**
 * @file segmentation_test.cpp
 * @brief Scan points, segmentation, templates, the in-view test and segment acceptance
 *        on scans of known polygons.
 */
#include <gtest/gtest.h>
#include <hymm/scanslam/IcpMatcher.h>
#include <hymm/scanslam/ScanLandmarkMap.h>
#include <hymm/scanslam/SegmentAcceptance.h>
#include <hymm/scanslam/Segmenter.h>
#include <hymm/scanslam/SogMatcher.h>
#include <hymm/sim/geometry.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <limits>
#include <string>

#include "sim_scenes.h"

using namespace hymm::scanslam;
using namespace hymm::scanslam::testing;

TEST(PointSetTest, PolarJacobianMatchesNumericDifferentiation)
{
    const double r = 7.3, b = 0.61, h = 1e-6;
    const auto f = [](double rr, double bb) { return Vec2(rr * std::cos(bb), rr * std::sin(bb)); };
    Mat2 num;
    num.col(0) = (f(r + h, b) - f(r - h, b)) / (2 * h);
    num.col(1) = (f(r, b + h) - f(r, b - h)) / (2 * h);
    EXPECT_LT((num - polarJacobian(r, b)).norm(), 1e-8);
    const Mat2 c = polarCovariance(r, b, {0.1, 0.02});
    // Along the beam the variance is the range's, across it (r sb)^2.
    const Vec2 along(std::cos(b), std::sin(b)), across(-std::sin(b), std::cos(b));
    EXPECT_NEAR(along.dot(c * along), 0.01, 1e-12);
    EXPECT_NEAR(across.dot(c * across), std::pow(r * 0.02, 2), 1e-12);
}

TEST(PointSetTest, BadReadingsAreSkippedAndCounted)
{
    mrpt::obs::CObservation2DRangeScan scan;
    scan.aperture = static_cast<float>(M_PI);
    scan.maxRange = 20;
    scan.resizeScan(5);
    const float vals[5] = {5.f, std::numeric_limits<float>::quiet_NaN(), 25.f, 0.f, 6.f};
    for (size_t i = 0; i < 5; ++i)
    {
        scan.setScanRange(i, vals[i]);
        scan.setScanRangeValidity(i, true);
    }
    scan.setScanRangeValidity(4, false);
    ScanReadStats st;
    const PointSet p = fromScan(scan, {}, &st);
    EXPECT_EQ(p.size(), 1u);
    EXPECT_EQ(st.used, 1u);
    EXPECT_EQ(st.non_finite, 1u);
    EXPECT_EQ(st.out_of_range, 2u);
    EXPECT_EQ(st.invalid, 1u);
    // Beam 0 of a right-to-left scan looks to the right.
    EXPECT_NEAR(p.bearing[0], -M_PI / 2, 1e-6);
    EXPECT_NEAR(p.points[0].y(), -5, 1e-5);

    // A scan with no valid return: no points, no segments.
    for (size_t i = 0; i < 5; ++i) scan.setScanRangeValidity(i, false);
    const PointSet none = fromScan(scan, {});
    EXPECT_TRUE(none.empty());
    EXPECT_TRUE(Segmenter({}).segment(none).empty());
}

TEST(SegmenterTest, EachSegmentLiesOnOneObject)
{
    const auto world = threeObjects();
    const PointSet scan = simulate(world, Vec3::Zero(), 3);
    Segmenter::Options o;
    o.min_points = 10;
    o.max_range_gap_m = 0.5;
    size_t short_runs = 0;
    const auto segs = Segmenter(o).segment(scan, &short_runs);
    ASSERT_EQ(segs.size(), 3u);
    std::vector<bool> seen(3, false);
    for (const auto& s : segs)
    {
        EXPECT_GE(s.size(), o.min_points);
        // The object whose outline is nearest the first point holds all of them.
        long best = -1;
        double bd = 1e9;
        for (const auto& obj : world.objects())
        {
            const double d = hymm::sim::pointPolygonDistance(scan.points[s.front()], obj.outlineAt(0));
            if (d < bd) bd = d, best = obj.id;
        }
        ASSERT_GE(best, 0);
        seen[static_cast<size_t>(best)] = true;
        const auto outline = world.objects()[static_cast<size_t>(best)].outlineAt(0);
        for (size_t i : s)
        {
            const Vec2& p = scan.points[i];
            double d = 1e9;
            for (size_t k = 0; k < outline.size(); ++k)
                d = std::min(d, hymm::sim::pointSegmentDistance(p, outline[k], outline[(k + 1) % outline.size()]));
            EXPECT_LT(d, 0.4);
        }
    }
    EXPECT_TRUE(seen[0] && seen[1] && seen[2]);

    // A stricter point count drops the smallest runs and counts them.
    o.min_points = 1000;
    EXPECT_TRUE(Segmenter(o).segment(scan, &short_runs).empty());
    EXPECT_GE(short_runs, 3u);
}

TEST(SegmenterTest, OptionsLoadAndThesisPreset)
{
    const auto t = Segmenter::Options::thesisRealData();
    EXPECT_EQ(t.min_points, 100u);
    EXPECT_DOUBLE_EQ(t.max_range_gap_m, 5.0);
    EXPECT_NEAR(t.max_angle_gap, 3 * M_PI / 180, 1e-15);
    mrpt::config::CConfigFileMemory cfg("[Seg]\nmin_points = 50\nmax_angle_gap_deg = 2\n");
    Segmenter::Options o;
    o.load(cfg, "Seg");
    EXPECT_EQ(o.min_points, 50u);
    EXPECT_NEAR(o.max_angle_gap, 2 * M_PI / 180, 1e-15);
    mrpt::config::CConfigFileMemory bad("[Seg]\nmin_pionts = 50\n");
    EXPECT_THROW(o.load(bad, "Seg"), std::exception);
    mrpt::config::CConfigFileMemory bad2("[Seg]\nmin_points = 1\n");
    EXPECT_THROW(o.load(bad2, "Seg"), std::exception);
}

// [ScanLandmarks], [ScanSegmentation], [ScanAcceptance]: each key declared once, so what
// a section saves it loads back, and absurd values are refused naming the key.
namespace
{
/** The three sections the Scan-SLAM source reads. */
struct ScanSlamSections
{
    ScanLandmarkMap::Options map;
    Segmenter::Options segmentation;
    SegmentAcceptance::Options acceptance;
    void load(const mrpt::config::CConfigFileBase& cfg)
    {
        map.load(cfg, "ScanLandmarks");
        segmentation.load(cfg, "ScanSegmentation");
        acceptance.load(cfg, "ScanAcceptance");
    }
    void save(mrpt::config::CConfigFileBase& cfg) const
    {
        map.save(cfg, "ScanLandmarks");
        segmentation.save(cfg, "ScanSegmentation");
        acceptance.save(cfg, "ScanAcceptance");
    }
};
}  // namespace

TEST(ScanSlamOptionsTest, SectionsSaveWhatTheyLoadAndRefuseAbsurdValues)
{
    mrpt::config::CConfigFileMemory cfg(
        "[ScanLandmarks]\nmatcher = icp\nmax_creation_range_m = 12\nwide_search = true\n"
        "view_std_phi_deg = 2\n[ScanSegmentation]\nmin_points = 40\nmax_angle_gap_deg = 2.5\n"
        "[ScanAcceptance]\ntrials = 4\ndisplacement_phi_deg = 5\nmax_cov_trace = 0.01\n");
    ScanSlamSections o;
    o.load(cfg);
    EXPECT_EQ(o.map.matcher, "icp");
    EXPECT_DOUBLE_EQ(o.map.max_creation_range_m, 12.0);
    EXPECT_TRUE(o.map.wide_search);
    EXPECT_EQ(o.segmentation.min_points, 40u);
    EXPECT_EQ(o.acceptance.trials, 4);
    EXPECT_NEAR(o.acceptance.displacement_phi, 5 * M_PI / 180, 1e-15);

    mrpt::config::CConfigFileMemory saved;
    o.save(saved);
    ScanSlamSections back;
    back.load(saved);
    EXPECT_EQ(back.map.matcher, o.map.matcher);
    EXPECT_DOUBLE_EQ(back.map.max_creation_range_m, o.map.max_creation_range_m);
    EXPECT_EQ(back.map.wide_search, o.map.wide_search);
    EXPECT_NEAR(back.map.view_std_phi, o.map.view_std_phi, 1e-15);
    EXPECT_EQ(back.segmentation.min_points, o.segmentation.min_points);
    EXPECT_NEAR(back.segmentation.max_angle_gap, o.segmentation.max_angle_gap, 1e-15);
    EXPECT_EQ(back.acceptance.trials, o.acceptance.trials);
    EXPECT_NEAR(back.acceptance.displacement_phi, o.acceptance.displacement_phi, 1e-15);
    EXPECT_DOUBLE_EQ(back.acceptance.max_cov_trace, o.acceptance.max_cov_trace);
    // Every key, as each section writes it.
    const auto keysOf = [](ScanSlamSections& x) {
        std::vector<std::string> out;
        for (const hymm::core::OptionTable& t : {x.map.table(), x.segmentation.table(), x.acceptance.table()})
            for (const auto& k : t.keys()) out.push_back(k.name + "=" + k.format());
        return out;
    };
    EXPECT_EQ(keysOf(back), keysOf(o));

    const auto refused = [](const std::string& section, const std::string& text, const std::string& key) {
        mrpt::config::CConfigFileMemory bad("[" + section + "]\n" + text + "\n");
        try
        {
            ScanSlamSections().load(bad);
        }
        catch (const std::exception& e)
        {
            return std::string(e.what()).find(key) != std::string::npos;
        }
        return false;
    };
    EXPECT_TRUE(refused("ScanLandmarks", "max_creation_range_m = 1e308", "max_creation_range_m"));
    EXPECT_TRUE(refused("ScanLandmarks", "wide_max_phi_deg = 720", "wide_max_phi_deg"));
    EXPECT_TRUE(refused("ScanSegmentation", "max_range_gap_m = 0", "max_range_gap_m"));
    EXPECT_TRUE(refused("ScanAcceptance", "trials = 1001", "trials"));
    EXPECT_TRUE(refused("ScanSegmentation", "max_angle_gap_deg = 181", "max_angle_gap_deg"));
    EXPECT_TRUE(refused("ScanSegmentation", "min_points = 1", "min_points"));
    EXPECT_TRUE(refused("ScanAcceptance", "displacement_xy_m = 0\ndisplacement_phi_deg = 0", "displacement_xy_m"));
    EXPECT_TRUE(refused("ScanAcceptance", "max_eror_fraction = 0.2", "max_eror_fraction"));
}

// [Laser] owns a laser return's noise: it sets the templates' noise, and [ScanLandmarks]'
// own key for the same quantity is then an error naming it.
TEST(ScanSlamOptionsTest, LaserSectionSetsTheTemplateNoise)
{
    mrpt::config::CConfigFileMemory laser("[Laser]\nstd_range_m = 0.2\nstd_bearing_deg = 2\n");
    const auto map = ScanLandmarkMap::fromConfig(&laser);
    EXPECT_DOUBLE_EQ(map->options().noise.std_range_m, 0.2);
    EXPECT_NEAR(map->options().noise.std_bearing, 2 * M_PI / 180, 1e-15);
    mrpt::config::CConfigFileMemory both("[ScanLandmarks]\nstd_bearing_deg = 1\n[Laser]\nstd_bearing_deg = 2\n");
    try
    {
        (void)ScanLandmarkMap::fromConfig(&both);
        ADD_FAILURE() << "both sections set the bearing noise";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("[ScanLandmarks] std_bearing_deg"), std::string::npos) << e.what();
    }
}

TEST(ScanTemplateTest, FrameAtCentroidAndInViewFraction)
{
    PointSet pts;
    for (int i = 0; i < 10; ++i) pts.add(Vec2(5 + 0.1 * i, 2), Mat2::Identity() * 1e-3);
    const ScanTemplate t = ScanTemplate::fromPoints(pts);
    EXPECT_NEAR(t.frame_in_sensor.x(), 5.45, 1e-12);
    EXPECT_NEAR(t.frame_in_sensor.y(), 2, 1e-12);
    EXPECT_EQ(t.frame_in_sensor.z(), 0);
    Vec2 c = Vec2::Zero();
    for (const Vec2& p : t.sog.points) c += p;
    EXPECT_LT(c.norm(), 1e-12);
    EXPECT_DOUBLE_EQ(fractionInView(t, t.frame_in_sensor, 30, M_PI), 1.0);
    EXPECT_DOUBLE_EQ(fractionInView(t, Vec3(-5, 0, 0), 30, M_PI), 0.0);  // behind
    EXPECT_DOUBLE_EQ(fractionInView(t, t.frame_in_sensor, 5.0, M_PI), 0.0);  // beyond range
    // Straddling the edge of the field of view: the points with x > 0 are in view.
    EXPECT_DOUBLE_EQ(fractionInView(t, Vec3(0.0, 3, 0), 30, M_PI), 0.5);
}

TEST(SegmentAcceptanceTest, CornersAcceptedFeaturelessSegmentsRejected)
{
    const auto world = threeObjects();
    const PointSet scan = simulate(world, Vec3::Zero(), 5);
    Segmenter::Options so;
    so.min_points = 10;
    const auto segs = Segmenter(so).segment(scan);
    ASSERT_EQ(segs.size(), 3u);
    const SogMatcher matcher;
    SegmentAcceptance::Options ao;
    ao.trials = 3;
    SegmentAcceptance acc(ao, matcher, 7);
    double wall_ratio = 0, corner_ratio = 0;
    for (const auto& s : segs)
    {
        PointSet seg;
        for (size_t i : s) seg.add(scan.points[i], scan.covs[i]);
        const bool wall = hymm::sim::pointPolygonDistance(seg.points.front(),
                                                          world.objects()[2].outlineAt(0)) < 0.5;
        double ratio = 0;
        const auto out = acc.test(seg, &ratio);
        if (wall)
            wall_ratio = ratio;
        else
        {
            EXPECT_EQ(out, SegmentAcceptance::Outcome::accepted) << "ratio " << ratio;
            corner_ratio = std::max(corner_ratio, ratio);
        }
    }
    // A straight wall is held along its length only by its two ends: worse than a corner.
    EXPECT_GT(wall_ratio, corner_ratio);
    EXPECT_EQ(acc.stats().total(), 3u);

    // The same flat wall with its ends cut off by the segment (a collinear run in the
    // middle of a long wall) cannot be registered along its length.
    PointSet flat;
    for (int i = 0; i < 60; ++i)
    {
        const double b = -0.3 + 0.01 * i;
        const double r = 10 / std::cos(b);
        flat.add(Vec2(10, r * std::sin(b)), polarCovariance(r, b, {0.05, 0.5 * M_PI / 180}));
    }
    // The self-test displaces a copy of the same points; their ends stay where they
    // were on the copy, so only a resampled line shows the ambiguity: check the
    // outcome is not an acceptance when the displacement is along the wall only.
    SegmentAcceptance::Options along = ao;
    along.displacement_phi = 0;
    SegmentAcceptance acc2(along, matcher, 8);
    double r2 = 0;
    acc2.test(flat, &r2);
    EXPECT_TRUE(std::isfinite(r2));

    // Degenerate input: too few points is counted, never a crash.
    PointSet two;
    two.add(Vec2(1, 1), Mat2::Identity() * 1e-2);
    two.add(Vec2(2, 1), Mat2::Identity() * 1e-2);
    EXPECT_EQ(acc.test(two), SegmentAcceptance::Outcome::too_small);
    // A small far object under heavy noise: the error is a large part of the displacement.
    PointSet noisy;
    for (int i = 0; i < 12; ++i)
    {
        const double b = 0.002 * i;
        noisy.add(Vec2(28 * std::cos(b), 28 * std::sin(b) + 0.05 * (i % 2)),
                  polarCovariance(28, b, {0.3, 3 * M_PI / 180}));
    }
    SegmentAcceptance::Options strict = ao;
    strict.min_extent_m = 0;
    SegmentAcceptance acc3(strict, matcher, 9);
    EXPECT_NE(acc3.test(noisy), SegmentAcceptance::Outcome::accepted);
}
