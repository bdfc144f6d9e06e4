// DenseSlam with the dense layers on the bundled chapter-3 rawlog: unidirectional
// information flow (the feature map and the path do not depend on the dense layers,
// bit for bit), regions hang off the filter's landmarks, and the dense_layers key.
#include <gtest/gtest.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/io/RawlogReader.h>
#include <hymm/io/ground_truth_io.h>
#include <hymm/sim/ground_truth_io.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <iostream>
#include <string>

namespace
{
using hymm::denseslam::DenseSlam;

const std::string kConfig = std::string(HYMM_SOURCE_DIR) + "/configs/ch3_slam.ini";
const std::string kRawlog = std::string(HYMM_SOURCE_DIR) + "/rawlogs/ch3_objects.rawlog";

// configs/ch3_slam.ini (landmark detector as landmark source) with the dense part set;
// fallback_m >= 0 replaces [HybridMetricMap] fallback_max_distance_m.
DenseSlam makeSlam(bool points, bool occupancy, bool classic, double fallback_m = -1)
{
    mrpt::config::CConfigFile cfg(kConfig);
    DenseSlam::Options o;
    o.loadFromConfigFile(cfg, "DenseSlam");
    EXPECT_EQ(o.point_sources, std::vector<std::string>{"bearing_range"});
    o.dense_layers.clear();
    if (points) o.dense_layers.emplace_back("points");
    if (occupancy) o.dense_layers.emplace_back("occupancy");
    o.classic_grid = classic;
    hymm::ekf::EkfSlam::Options e;
    e.loadFromConfigFile(cfg, "EkfSlam");
    DenseSlam::DenseOptions d;
    d.loadFromConfigFile(cfg);
    if (fallback_m >= 0) d.hybrid.fallback_max_distance_m = fallback_m;
    return DenseSlam(o, e, d, &cfg);
}

void runRawlog(DenseSlam& slam)
{
    hymm::io::RawlogReader reader(kRawlog);
    hymm::io::RawlogEntry entry;
    while (reader.next(entry)) slam.processEntry(entry);
}

TEST(DenseSlamDense, FeatureMapAndPathAreBitwiseIdenticalWithAndWithoutDenseLayers)
{
    DenseSlam plain = makeSlam(false, false, false);
    DenseSlam dense = makeSlam(true, true, true);
    ASSERT_EQ(plain.partition(), nullptr);
    ASSERT_EQ(plain.hybridMap(), nullptr);
    ASSERT_EQ(plain.classicGrid(), nullptr);
    ASSERT_NE(dense.partition(), nullptr);
    ASSERT_NE(dense.hybridMap(), nullptr);
    ASSERT_NE(dense.classicGrid(), nullptr);
    runRawlog(plain);
    runRawlog(dense);

    // The dense part really ran (otherwise the comparison proves nothing).
    EXPECT_GT(dense.partition()->size(), 0u);
    EXPECT_GT(dense.stats().returns_stored, 0u);
    EXPECT_GT(dense.hybridMap()->size(), 0u);
    EXPECT_EQ(plain.stats().returns_stored, 0u);

    ASSERT_GT(plain.ekf().numLandmarks(), 3u);
    EXPECT_EQ(plain.ekf().landmarkIds(), dense.ekf().landmarkIds());
    ASSERT_EQ(plain.ekf().mean().size(), dense.ekf().mean().size());
    EXPECT_TRUE(plain.ekf().mean() == dense.ekf().mean());
    EXPECT_TRUE(plain.ekf().cov() == dense.ekf().cov());
    ASSERT_EQ(plain.path().size(), dense.path().size());
    for (size_t i = 0; i < plain.path().size(); ++i)
    {
        ASSERT_EQ(plain.path()[i].t, dense.path()[i].t) << "sample " << i;
        ASSERT_TRUE(plain.path()[i].pose == dense.path()[i].pose) << "sample " << i;
        ASSERT_TRUE(plain.path()[i].cov == dense.path()[i].cov) << "sample " << i;
    }

    // Every region hangs off landmarks of the feature map or virtual landmarks carried
    // as passive states (at most one per region), at their current estimates.
    EXPECT_GT(dense.stats().virtual_landmarks, 0u);
    EXPECT_EQ(dense.virtualLandmarkIds().size(), dense.ekf().passive().numBlocks());
    size_t with_virtual = 0;
    for (long id : dense.partition()->regionIds())
    {
        const auto& r = dense.partition()->region(id);
        int virtuals = 0;
        for (int k = 0; k < 3; ++k)
        {
            const long v = r.vertex_ids[k];
            if (dense.virtualLandmarkIds().count(v))
            {
                ++virtuals;
                ASSERT_TRUE(dense.ekf().passive().has(v));
                EXPECT_TRUE((r.current[k] - dense.ekf().passive().mean(v)).norm() < 1e-9);
                continue;
            }
            ASSERT_TRUE(dense.ekf().hasLandmark(v)) << "region " << id;
            EXPECT_TRUE((r.current[k] - dense.ekf().landmarkMean(v)).norm() < 1e-9)
                << "region " << id << " vertex " << k;
        }
        EXPECT_LE(virtuals, 1) << "region " << id;
        with_virtual += virtuals;
    }
    EXPECT_GT(with_virtual, 0u);
}

TEST(DenseSlamDense, DenseLayersKey)
{
    const auto parse = [](const std::string& value)
    {
        mrpt::config::CConfigFileMemory cfg;
        cfg.write("DenseSlam", "dense_layers", value);
        DenseSlam::Options o;
        o.loadFromConfigFile(cfg, "DenseSlam");
        return std::make_pair(o.denseLayer("points"), o.denseLayer("occupancy"));
    };
    EXPECT_EQ(parse("none"), std::make_pair(false, false));
    EXPECT_EQ(parse("points"), std::make_pair(true, false));
    EXPECT_EQ(parse("occupancy"), std::make_pair(false, true));
    EXPECT_EQ(parse("points, occupancy"), std::make_pair(true, true));
    EXPECT_EQ(parse("occupancy,points"), std::make_pair(true, true));
    EXPECT_ANY_THROW(parse("points,grid"));
    EXPECT_ANY_THROW(parse("sog,particles,sog"));
    EXPECT_ANY_THROW(parse("points,points"));
    EXPECT_ANY_THROW(parse(""));

    mrpt::config::CConfigFileMemory none;
    DenseSlam::Options o;
    o.loadFromConfigFile(none, "DenseSlam");
    EXPECT_FALSE(o.denseLayers());
    EXPECT_FALSE(o.classic_grid);

    // The chapter-4 layers: any subset, written back in a canonical order.
    {
        mrpt::config::CConfigFileMemory cfg;
        cfg.write("DenseSlam", "dense_layers", "property, sog,particles");
        DenseSlam::Options p;
        p.loadFromConfigFile(cfg, "DenseSlam");
        EXPECT_EQ(p.dense_layers, (std::vector<std::string>{"particles", "sog", "property"}));
        EXPECT_FALSE(p.denseLayer("points") || p.denseLayer("occupancy"));
        EXPECT_TRUE(p.denseLayers());
        mrpt::config::CConfigFileMemory back;
        p.saveToConfigFile(back, "DenseSlam");
        EXPECT_EQ(back.read_string("DenseSlam", "dense_layers", ""), "particles,sog,property");
        const DenseSlam s(p, hymm::ekf::EkfSlam::Options());
        ASSERT_NE(s.hybridMap(), nullptr);
        EXPECT_EQ(s.hybridMap()->enabledKinds(), (std::vector<std::string>{"particles", "sog", "property"}));
    }

    // Only the layers named in [DenseSlam] are built.
    DenseSlam::Options only_points;
    only_points.dense_layers = {"points"};
    const DenseSlam s(only_points, hymm::ekf::EkfSlam::Options());
    ASSERT_NE(s.hybridMap(), nullptr);
    EXPECT_TRUE(s.hybridMap()->options().enable_points);
    EXPECT_FALSE(s.hybridMap()->options().enable_occupancy);
    EXPECT_EQ(s.classicGrid(), nullptr);
    // A kind no layer table row names is refused when the options are set in code.
    DenseSlam::Options unknown;
    unknown.dense_layers = {"voxels"};
    EXPECT_THROW(DenseSlam(unknown, hymm::ekf::EkfSlam::Options()),
                 std::invalid_argument);
}

// max_local_std_m (Sec. 3.6, 3.7.3): scans are fused into a region only while the vehicle
// is known well relative to its vertices. The feature map does not change; what is
// withheld is counted; what is fused is closer to the true outlines.
TEST(DenseSlamDense, LocalUncertaintyGateWithholdsPoorlyLocalisedReturns)
{
    // The gate alone: no fallback on either side.
    DenseSlam on = makeSlam(true, false, false, 0.0);
    ASSERT_DOUBLE_EQ(on.options().max_local_std_m, 0.15);  // configs/ch3_slam.ini
    mrpt::config::CConfigFile cfg(kConfig);
    DenseSlam::Options o;
    o.loadFromConfigFile(cfg, "DenseSlam");
    o.dense_layers = {"points"};
    o.classic_grid = false;
    o.max_local_std_m = 0.0;
    hymm::ekf::EkfSlam::Options e;
    e.loadFromConfigFile(cfg, "EkfSlam");
    DenseSlam::DenseOptions d;
    d.loadFromConfigFile(cfg);
    d.hybrid.fallback_max_distance_m = 0.0;
    DenseSlam off(o, e, d);
    runRawlog(off);
    runRawlog(on);

    ASSERT_EQ(on.path().size(), off.path().size());
    for (size_t i = 0; i < on.path().size(); ++i) ASSERT_EQ(on.path()[i].pose, off.path()[i].pose);
    EXPECT_EQ(off.stats().returns_withheld, 0u);
    EXPECT_GT(on.stats().returns_withheld, 0u);
    EXPECT_GT(on.stats().returns_stored, 0u);
    // Every return is either stored, withheld or outside; the regions are the same.
    EXPECT_EQ(on.stats().returns_stored + on.stats().returns_withheld, off.stats().returns_stored);
    EXPECT_EQ(on.partition()->regionIds(), off.partition()->regionIds());

    // True surfaces: object outlines and the trunks of the true landmarks.
    std::vector<hymm::dense::Polygon> surfaces;
    for (const auto& r : hymm::sim::readObjectOutlines(std::string(HYMM_SOURCE_DIR) +
                                                       "/rawlogs/ch3_objects_gt_objects.txt"))
        surfaces.emplace_back(r.outline.begin(), r.outline.end());
    const auto gt = hymm::io::loadGroundTruth(
        "", std::string(HYMM_SOURCE_DIR) + "/rawlogs/ch3_objects_gt_landmarks.csv");
    for (const auto& l : gt.landmarks)  // "id,x,y,radius": the trunks
        surfaces.push_back(hymm::dense::circlePolygon(Eigen::Vector2d(l.x, l.y),
                                                      l.extra.empty() ? 0.0 : l.extra[0]));
    const auto error = [&](DenseSlam& s) {
        s.refreshRegions();
        mrpt::maps::CSimplePointsMap pts;
        s.hybridMap()->renderPoints(*s.partition(), pts);
        return hymm::dense::evaluateOutlines(hymm::dense::pointsOf(pts), surfaces).mean_distance_m;
    };
    const double e_on = error(on), e_off = error(off);
    EXPECT_LT(e_on, e_off) << "gate " << e_on << " m, no gate " << e_off << " m";
    std::cout << "mean distance to the true surfaces: gate " << e_on << " m, no gate " << e_off << " m\n";
}

// The fallback ([HybridMetricMap] fallback_max_distance_m, on in configs/ch3_slam.ini)
// keeps returns in no region in the frame of the nearest region: the filter does not see
// it (path and landmarks bitwise the same), the books balance, the regions hold what they
// hold without it, and the map covers more of the true outlines, close to them.
TEST(DenseSlamDense, FallbackKeepsReturnsInNoRegionAndTheBooksBalance)
{
    DenseSlam on = makeSlam(true, true, false);
    DenseSlam off = makeSlam(true, true, false, 0.0);
    ASSERT_GT(on.hybridMap()->options().fallback_max_distance_m, 0.0);
    runRawlog(on);
    runRawlog(off);
    ASSERT_EQ(on.path().size(), off.path().size());
    for (size_t i = 0; i < on.path().size(); ++i) ASSERT_EQ(on.path()[i].pose, off.path()[i].pose);
    ASSERT_EQ(on.ekf().mean(), off.ekf().mean());
    const auto& a = on.stats();
    const auto& b = off.stats();
    EXPECT_EQ(a.returns_stored, b.returns_stored);
    EXPECT_EQ(a.returns_outside, b.returns_outside);
    EXPECT_EQ(a.returns_withheld, b.returns_withheld);
    EXPECT_EQ(b.returns_fallback + b.returns_withheld_fallback, 0u);
    EXPECT_EQ(b.returns_dropped, b.returns_outside);
    EXPECT_EQ(a.returns_fallback + a.returns_dropped, a.returns_outside);  // no delayed store
    EXPECT_GT(a.returns_fallback, a.returns_outside / 2);
    EXPECT_LE(a.returns_withheld_fallback, a.returns_withheld);
    // The per-cell tally of the returns in no region holds every one of them.
    size_t tallied = 0, kept = 0;
    for (const auto& r : on.outsideReturnCells())
    {
        tallied += r.returns;
        kept += r.kept;
        EXPECT_GE(r.returns, r.kept);
        EXPECT_TRUE(r.p.allFinite());
    }
    EXPECT_EQ(tallied, a.returns_outside);
    EXPECT_EQ(kept, a.returns_fallback);
    EXPECT_LT(on.outsideReturnCells().size(), a.returns_outside);  // returns share cells

    std::vector<hymm::dense::Polygon> outlines;
    for (const auto& r : hymm::sim::readObjectOutlines(std::string(HYMM_SOURCE_DIR) +
                                                       "/rawlogs/ch3_objects_gt_objects.txt"))
        outlines.emplace_back(r.outline.begin(), r.outline.end());
    auto surfaces = outlines;
    const auto gt = hymm::io::loadGroundTruth(
        "", std::string(HYMM_SOURCE_DIR) + "/rawlogs/ch3_objects_gt_landmarks.csv");
    for (const auto& l : gt.landmarks)  // "id,x,y,radius": the trunks
        surfaces.push_back(hymm::dense::circlePolygon(Eigen::Vector2d(l.x, l.y),
                                                      l.extra.empty() ? 0.0 : l.extra[0]));
    const auto score = [&](DenseSlam& s, hymm::dense::HybridMetricMap::Content c) {
        s.refreshRegions();
        mrpt::maps::CSimplePointsMap pts;
        s.hybridMap()->renderPoints(*s.partition(), pts, c);
        const auto p = hymm::dense::pointsOf(pts);
        return std::make_pair(hymm::dense::evaluateOutlines(p, surfaces).mean_distance_m,
                              hymm::dense::evaluateOutlines(p, outlines).coverage);
    };
    using C = hymm::dense::HybridMetricMap::Content;
    const auto all_on = score(on, C::All), all_off = score(off, C::All), fb = score(on, C::Fallback),
               regions_on = score(on, C::Regions);
    EXPECT_EQ(regions_on, all_off);  // the regions' content does not change
    EXPECT_GT(all_on.second, 1.5 * all_off.second);
    EXPECT_LT(all_on.first, 0.3);
    EXPECT_LT(fb.first, 0.3);
    std::cout << "points: coverage " << all_off.second << " -> " << all_on.second << ", mean distance "
              << all_off.first << " -> " << all_on.first << " m (fallback alone " << fb.first << " m)\n";
}

TEST(DenseSlamDense, UnknownKeyInADenseSectionIsAnError)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("LtrPartition", "no_such_key", 1);
    DenseSlam::DenseOptions d;
    EXPECT_ANY_THROW(d.loadFromConfigFile(cfg));
}

}  // namespace
