// ScanLandmarkMap (the Scan-SLAM step of one scan) on scans of known polygons: landmarks
// are created from corners and re-observed, and bad input (empty and all-invalid scans,
// a straight wall, a scan far from the prediction) is counted, never a throw or a NaN.
#include <gtest/gtest.h>
#include <mrpt/core/Clock.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <hymm/ekf/pose_landmark_model.h>
#include <hymm/scanslam/ScanLandmarkMap.h>

#include <mrpt/poses/CPosePDFGaussian.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "sim_scenes.h"

namespace
{
using namespace hymm::scanslam;
using namespace hymm::scanslam::testing;

mrpt::obs::CObservation2DRangeScan::Ptr scanAt(const hymm::sim::World& w, const Vec3& pose, uint32_t seed)
{
    return simulatedScan(w, pose, seed);  // Laser{}: 0.05 m, 0.5 deg, 30 m, 0.5 deg beams
}

std::unique_ptr<ScanLandmarkMap> makeMap(ScanLandmarkMap::Options o = {})
{
    o.noise = {0.05, 0.5 * M_PI / 180};
    Segmenter::Options s;
    s.min_points = 10;
    SegmentAcceptance::Options a;
    return std::make_unique<ScanLandmarkMap>(o, s, a, makeMatcher("sog"));
}

hymm::ekf::EkfSlam makeEkf()
{
    hymm::ekf::EkfSlam ekf{hymm::ekf::EkfSlam::Options{}};
    ekf.reset(Eigen::Vector3d::Zero(), 1e-6 * Eigen::Matrix3d::Identity());
    return ekf;
}

void expectFinite(const hymm::ekf::EkfSlam& ekf)
{
    EXPECT_TRUE(ekf.mean().allFinite());
    EXPECT_TRUE(ekf.cov().allFinite());
}

hymm::sim::World boxes()
{
    std::vector<hymm::sim::WorldObject> objs;
    objs.push_back(fixedObject(0, box(4, 3), 9, 4, 0.5));
    objs.push_back(fixedObject(1, box(3, 2), 8, -6, 0.6));
    return hymm::sim::World({}, std::move(objs));
}

/** A map with options `o` and a filter loaded from `map` and `ekf` saved together (the
 *  run state's order: map, then filter). */
std::pair<std::unique_ptr<ScanLandmarkMap>, hymm::ekf::EkfSlam> reloaded(const ScanLandmarkMap& map,
                                                                          const hymm::ekf::EkfSlam& ekf,
                                                                          const ScanLandmarkMap::Options& o)
{
    mrpt::io::CMemoryStream mem;
    auto out = mrpt::serialization::archiveFrom(mem);
    map.saveState(out);
    ekf.saveState(out);
    mem.Seek(0);
    auto in = mrpt::serialization::archiveFrom(mem);
    auto map2 = makeMap(o);
    auto ekf2 = makeEkf();
    map2->loadState(in);
    ekf2.loadState(in);
    return {std::move(map2), std::move(ekf2)};
}

/** A map with options `o` and its filter after one scan of boxes() from the origin. */
std::pair<std::unique_ptr<ScanLandmarkMap>, hymm::ekf::EkfSlam> afterFirstScan(const ScanLandmarkMap::Options& o,
                                                                               uint32_t seed)
{
    auto map = makeMap(o);
    auto ekf = makeEkf();
    map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), seed));
    return {std::move(map), std::move(ekf)};
}

TEST(ScanLandmarkMap, CreatesFromCornersAndReobservesThem)
{
    auto map = makeMap();
    auto ekf = makeEkf();
    map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), 1));
    const size_t created = map->stats().created;
    ASSERT_GE(created, 1u);
    // Every segment became a landmark or was rejected for a counted reason.
    const auto& s0 = map->stats();
    size_t rejected = s0.segments_far + s0.segments_collinear + s0.creation_failed;
    for (size_t k = 1; k < SegmentAcceptance::kOutcomes; ++k) rejected += s0.acceptance[k];
    EXPECT_EQ(created + rejected, s0.segments);
    EXPECT_EQ(map->templates().size(), created);
    for (int k = 0; k < 3; ++k) map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), 2 + k));
    // The same scene again: every landmark observed, none twice on one object (a
    // segment the random self-test refused before may pass now: two boxes, two at most).
    EXPECT_LE(map->stats().created, 2u);
    EXPECT_GE(map->stats().updated, 3 * created);
    EXPECT_LE(map->stats().gated, 1u);
    expectFinite(ekf);
    // The vehicle stays where it is (it did not move, the scans say so).
    EXPECT_LT(ekf.vehiclePose().head<2>().norm(), 0.05);
}

TEST(ScanLandmarkMap, EmptyAndInvalidScansAreCounted)
{
    auto map = makeMap();
    auto ekf = makeEkf();
    mrpt::obs::CObservation2DRangeScan empty;
    empty.aperture = static_cast<float>(M_PI);
    empty.maxRange = 30;
    map->processScan(ekf, empty);
    auto bad = scanAt(boxes(), Vec3::Zero(), 3);
    for (size_t i = 0; i < bad->getScanSize(); ++i)
        bad->setScanRange(i, i % 2 ? std::numeric_limits<float>::quiet_NaN() : -1.0f);
    map->processScan(ekf, *bad);
    EXPECT_EQ(map->stats().scans, 2u);
    EXPECT_EQ(map->stats().scans_empty, 2u);
    EXPECT_EQ(map->stats().beams_invalid, bad->getScanSize());
    EXPECT_EQ(map->stats().created, 0u);
    expectFinite(ekf);
}

TEST(ScanLandmarkMap, StraightWallIsNotALandmark)
{
    auto map = makeMap();
    auto ekf = makeEkf();
    std::vector<hymm::sim::WorldObject> objs;
    objs.push_back(fixedObject(0, box(10, 0.1), 10, 0, M_PI / 2));  // a wall seen face-on
    const hymm::sim::World wall({}, std::move(objs));
    map->processScan(ekf, *scanAt(wall, Vec3::Zero(), 4));
    const auto& s = map->stats();
    EXPECT_GE(s.segments, 1u);
    EXPECT_EQ(s.created, 0u);
    // Rejected as collinear or by the acceptance test, and counted.
    size_t rejected = s.segments_collinear;
    for (size_t k = 1; k < SegmentAcceptance::kOutcomes; ++k) rejected += s.acceptance[k];
    EXPECT_EQ(rejected, s.segments - s.segments_far);
    EXPECT_FALSE(hasOrientation(PointSet{{Vec2(0, 0), Vec2(1, 0), Vec2(2, 0)}, {Mat2::Identity(), Mat2::Identity(), Mat2::Identity()}, {}, {}}, 0.05));
}

TEST(ScanLandmarkMap, ScanFarFromThePredictionIsCountedNotFused)
{
    auto map = makeMap();
    auto ekf = makeEkf();
    map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), 5));
    ASSERT_GE(map->stats().created, 1u);
    const Eigen::VectorXd x_before = ekf.mean();
    // The vehicle really moved 4 m sideways and turned, the filter does not know it: the
    // templates are predicted where nothing matches them.
    map->processScan(ekf, *scanAt(boxes(), Vec3(0, 4.0, 0.6), 6));
    const auto& s = map->stats();
    size_t failed = 0;
    for (const auto& [reason, n] : s.align_failed) failed += n;
    EXPECT_GT(failed + s.gated + s.out_of_view, 0u);
    EXPECT_EQ(s.updated, 0u);
    expectFinite(ekf);
    EXPECT_TRUE(ekf.vehiclePose().isApprox(x_before.head<3>()));
}

/** Moves the filter's vehicle by `d` (vehicle frame) with covariance diag(var_xy, var_xy, var_phi). */
void drive(hymm::ekf::EkfSlam& ekf, const Vec3& d, double var_xy, double var_phi)
{
    mrpt::math::CMatrixDouble33 c;
    c.setZero();
    c(0, 0) = c(1, 1) = var_xy;
    c(2, 2) = var_phi;
    ekf.predictOdometry(mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(d.x(), d.y(), d.z()), c));
}

TEST(ScanLandmarkMap, ViewpointTermGrowsWithTheDisplacementSinceCreation)
{
    ScanLandmarkMap::Options o;
    o.view_std_xy_m = 0.2;
    o.view_std_xy_per_m = 0.1;
    o.view_std_phi = 2 * M_PI / 180;
    o.view_std_phi_per_m = 0.5 * M_PI / 180;
    auto map = makeMap(o);
    auto ekf = makeEkf();
    map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), 1));
    ASSERT_GE(map->stats().created, 1u);
    drive(ekf, Vec3(2, 0, 0), 1e-4, 1e-6);
    map->processScan(ekf, *scanAt(boxes(), Vec3(2, 0, 0), 8));
    ASSERT_FALSE(map->lastAligned().empty());
    for (const auto& a : map->lastAligned())
    {
        const Vec3& made = map->templates().at(a.id).frame_in_sensor;
        const double d = (a.z_hat.head<2>() - made.head<2>()).norm();
        EXPECT_NEAR(d, 2.0, 0.05);  // the vehicle drove 2 m straight on
        const double s_xy = 0.2 + 0.1 * d, s_phi = (2 + 0.5 * d) * M_PI / 180;
        // R = the matcher's (positive definite) plus the viewpoint term.
        EXPECT_GT(a.R(0, 0), s_xy * s_xy);
        EXPECT_GT(a.R(1, 1), s_xy * s_xy);
        EXPECT_GT(a.R(2, 2), s_phi * s_phi);
        EXPECT_LT(a.R(0, 0), s_xy * s_xy + 0.05);
    }
    EXPECT_GE(map->stats().updated, 1u);
    expectFinite(ekf);
}

TEST(ScanLandmarkMap, UncertainPredictionsAndLargeViewChangesAreNotAligned)
{
    ScanLandmarkMap::Options o;
    o.max_prediction_std_m = 0.5;
    auto map = makeMap(o);
    auto ekf = makeEkf();
    map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), 5));
    const size_t created = map->stats().created;
    ASSERT_GE(created, 1u);
    // Odometry that knows little (std 2 m): every template's predicted position is
    // that uncertain relative to the sensor, beyond the matcher's local basin.
    drive(ekf, Vec3::Zero(), 4.0, 1e-6);
    map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), 10));
    EXPECT_GE(map->stats().prediction_uncertain, created);
    EXPECT_EQ(map->stats().aligned, 0u);
    EXPECT_EQ(map->stats().updated, 0u);

    o.max_prediction_std_m = 0;
    o.max_view_change_m = 1.0;
    auto [far, ekf2] = afterFirstScan(o, 1);
    ASSERT_GE(far->stats().created, 1u);
    drive(ekf2, Vec3(2, 0, 0), 1e-4, 1e-6);
    far->processScan(ekf2, *scanAt(boxes(), Vec3(2, 0, 0), 12));
    EXPECT_GE(far->stats().view_changed, 1u);
    EXPECT_EQ(far->stats().aligned, 0u);
    expectFinite(ekf2);
}

/** Points every 5 cm along the outline of box(l, w) placed at (x, y, yaw), as the dense
 *  map's Gaussians (global frame) with the anisotropic covariance `c`. */
void addOutline(PointSet& out, double l, double w, double x, double y, double yaw, const Mat2& c)
{
    const auto poly = box(l, w);
    for (size_t k = 0; k < poly.size(); ++k)
    {
        const Vec2 a = poly[k], b = poly[(k + 1) % poly.size()];
        const int n = static_cast<int>(std::ceil((b - a).norm() / 0.05));
        for (int i = 0; i < n; ++i)
            out.add(transformPoint(Vec3(x, y, yaw), a + (b - a) * (static_cast<double>(i) / n)), c);
    }
}

/** The dense map of boxes(): both outlines, plus a decoy 40 m away that no template's
 *  surroundings reach. */
PointSet denseBoxes(const Mat2& c)
{
    PointSet d;
    addOutline(d, 4, 3, 9, 4, 0.5, c);
    addOutline(d, 3, 2, 8, -6, 0.6, c);
    addOutline(d, 2, 2, 40, 40, 0, c);
    return d;
}

// Thesis 6.2: the dense map around a template, placed in the landmark's frame at the
// filter's estimate, is added to it; its own points stay first and unchanged.
TEST(ScanLandmarkMap, AugmentedTemplateIsTheDenseMapAroundItInItsFrame)
{
    ScanLandmarkMap::Options o;
    o.augment_margin_m = 1.0;
    o.augment_max_points = 120;
    auto [map, ekf] = afterFirstScan(o, 1);
    ASSERT_GE(map->stats().created, 1u);
    Mat2 c;
    c << 0.04, 0.01, 0.01, 0.02;
    const PointSet dense = denseBoxes(c);
    size_t queries = 0;
    map->setAugmenter([&](const Vec2& lo, const Vec2& hi) {
        ++queries;
        PointSet in;
        for (size_t i = 0; i < dense.size(); ++i)
            if ((dense.points[i].array() >= lo.array()).all() && (dense.points[i].array() <= hi.array()).all())
                in.add(dense.points[i], dense.covs[i]);
        return in;
    });
    for (const auto& [id, tpl] : map->templates())
    {
        const ScanTemplate aug = map->augmentedTemplate(ekf, id, tpl);
        ASSERT_GT(aug.sog.size(), tpl.sog.size());
        EXPECT_LE(aug.sog.size() - tpl.sog.size(), o.augment_max_points);
        for (size_t i = 0; i < tpl.sog.size(); ++i) EXPECT_EQ(aug.sog.points[i], tpl.sog.points[i]);
        Vec2 lo = tpl.sog.points[0], hi = lo;
        for (const Vec2& p : tpl.sog.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
        const Vec3 frame = ekf.landmarkBlockMean(id).head<3>();
        const Mat2 R = rotation(frame.z());
        for (size_t i = tpl.sog.size(); i < aug.sog.size(); ++i)
        {
            const Vec2& q = aug.sog.points[i];
            EXPECT_TRUE((q.array() >= lo.array() - 1.0 - 1e-9).all() && (q.array() <= hi.array() + 1.0 + 1e-9).all());
            // Back in the global frame it is one of the dense map's points, with its covariance.
            const Vec2 g = transformPoint(frame, q);
            double best = 1e9;
            for (const Vec2& p : dense.points) best = std::min(best, (p - g).norm());
            EXPECT_LT(best, 1e-9);
            EXPECT_LT((R * aug.sog.covs[i] * R.transpose() - c).norm(), 1e-12);
            EXPECT_LT(g.norm(), 30.0);  // never the decoy
        }
    }
    EXPECT_EQ(queries, map->templates().size());
}

// The dense map is read only once the prediction is uncertain beyond
// augment_above_std_m, each use counted; an empty neighbourhood is counted, not an error.
TEST(ScanLandmarkMap, AugmentationOnlyPastTheUncertaintyThresholdAndCounted)
{
    ScanLandmarkMap::Options o;
    o.augment_above_std_m = 0.3;
    auto map = makeMap(o);
    auto ekf = makeEkf();
    const PointSet dense = denseBoxes(0.01 * Mat2::Identity());
    bool empty = false;
    map->setAugmenter([&](const Vec2&, const Vec2&) { return empty ? PointSet{} : dense; });
    map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), 1));
    const size_t created = map->stats().created;
    ASSERT_GE(created, 1u);
    drive(ekf, Vec3(0.5, 0, 0), 1e-4, 1e-6);
    map->processScan(ekf, *scanAt(boxes(), Vec3(0.5, 0, 0), 2));
    EXPECT_EQ(map->stats().augmented, 0u);  // certain: the templates alone
    EXPECT_GE(map->stats().updated, created);
    // The vehicle drove 1 m more than odometry says, with std 0.5 m: the templates'
    // predictions are uncertain, the augmented ones align and correct the pose.
    drive(ekf, Vec3(0.5, 0, 0), 0.25, 1e-6);
    map->processScan(ekf, *scanAt(boxes(), Vec3(1.5, 0, 0), 3));
    EXPECT_GE(map->stats().augmented, created);
    EXPECT_GE(map->stats().augment_points, map->stats().augmented);
    EXPECT_EQ(map->stats().augment_empty, 0u);
    EXPECT_NEAR(ekf.vehiclePose().x(), 1.5, 0.1);
    EXPECT_NEAR(ekf.vehiclePose().y(), 0.0, 0.1);
    expectFinite(ekf);
    empty = true;
    drive(ekf, Vec3(0, 0, 0), 0.25, 1e-6);
    map->processScan(ekf, *scanAt(boxes(), Vec3(1.5, 0, 0), 4));
    EXPECT_GE(map->stats().augment_empty, 1u);
}

// The augmented template is what the matcher aligns: a dense map that puts the objects
// 0.3 m off moves the correction away from the one the true dense map gives.
TEST(ScanLandmarkMap, AugmentedTemplateIsWhatTheMatcherAligns)
{
    ScanLandmarkMap::Options o;
    o.augment_above_std_m = 0.3;
    std::vector<double> y;
    for (const double shift : {0.0, 0.3})
    {
        auto [map, ekf] = afterFirstScan(o, 1);
        ASSERT_GE(map->stats().created, 1u);
        PointSet dense = denseBoxes(0.01 * Mat2::Identity());
        for (Vec2& p : dense.points) p.y() += shift;
        map->setAugmenter([dense](const Vec2&, const Vec2&) { return dense; });
        drive(ekf, Vec3(0.5, 0, 0), 0.25, 1e-6);
        map->processScan(ekf, *scanAt(boxes(), Vec3(1.0, 0, 0), 3));
        EXPECT_GE(map->stats().augmented, 1u);
        EXPECT_GE(map->stats().updated, 1u);
        expectFinite(ekf);
        y.push_back(ekf.vehiclePose().y());
    }
    RecordProperty("vehicle_y_true_dense", std::to_string(y[0]));
    RecordProperty("vehicle_y_shifted_dense", std::to_string(y[1]));
    EXPECT_GT(std::abs(y[1] - y[0]), 0.05);
}

// merge_duplicates: a second landmark on an object already held (here the first one's
// template added again 0.4 m and 3 deg off, as a drifted lap would make it) is aligned
// with the first, fused into it as a relative pose and removed; without the option both
// stay. A pair that does not align is not tried again for merge_retry_scans.
TEST(ScanLandmarkMap, DuplicateOfALandmarkIsMergedIntoIt)
{
    for (const bool merge : {false, true})
    {
        SCOPED_TRACE(merge ? "merge" : "no merge");
        ScanLandmarkMap::Options o;
        o.merge_duplicates = merge;
        auto [map, ekf] = afterFirstScan(o, 1);
        ASSERT_FALSE(map->templates().empty());
        const long first = map->templates().begin()->first;
        const Vec3 z = hymm::ekf::poseLandmarkObservation(ekf.vehiclePose(), ekf.landmarkBlockMean(first).head<3>(),
                                                          Vec3::Zero());
        AlignResult dup;
        dup.ok = true;
        dup.z = z + Vec3(0.4, -0.2, 3 * M_PI / 180);
        dup.R = Eigen::Vector3d(0.2, 0.2, 0.05).cwiseAbs2().asDiagonal();
        const long second = map->addTemplateLandmark(ekf, map->templates().at(first), dup, Vec3::Zero());
        const size_t before = map->templates().size();
        for (int k = 0; k < 2; ++k) map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), 2 + k));
        expectFinite(ekf);
        const auto& st = map->stats();
        if (!merge)
        {
            EXPECT_EQ(st.merge_candidates, 0u);
            EXPECT_TRUE(ekf.hasLandmark(second));
            EXPECT_GE(map->templates().size(), before);
            continue;
        }
        EXPECT_EQ(st.merged, 1u);
        EXPECT_EQ(st.merge_candidates, st.merged + st.merge_align_failed + st.merge_gated);
        EXPECT_FALSE(ekf.hasLandmark(second));
        EXPECT_EQ(map->templates().count(second), 0u);
        EXPECT_TRUE(ekf.hasLandmark(first));
        // The one left is where the scans put it (the vehicle has not moved).
        const Vec3 z_after = hymm::ekf::poseLandmarkObservation(ekf.vehiclePose(), ekf.landmarkBlockMean(first).head<3>(),
                                                                Vec3::Zero());
        EXPECT_LT((z_after - z).head<2>().norm(), 0.1);
        EXPECT_LT(std::abs(z_after.z() - z.z()), 2 * M_PI / 180);
    }
}

// A pair that fails to merge waits merge_retry_scans scans, and that wait is part of the
// saved run state: a map saved and loaded after a failed attempt continues exactly as the
// original (same counters, same filter, bit for bit).
TEST(ScanLandmarkMap, FailedMergeWaitsAndIsPartOfTheSavedState)
{
    ScanLandmarkMap::Options o;
    o.merge_duplicates = true;
    auto [map, ekf] = afterFirstScan(o, 1);
    ASSERT_FALSE(map->templates().empty());
    const long first = map->templates().begin()->first;
    // A "duplicate" that is the first template mirrored: it overlaps the object but its
    // shape does not fit the original's, so the merge is refused (no alignment or gated).
    ScanTemplate mirrored = map->templates().at(first);
    for (Vec2& p : mirrored.sog.points) p.x() = -p.x();
    AlignResult dup;
    dup.ok = true;
    dup.z = hymm::ekf::poseLandmarkObservation(ekf.vehiclePose(), ekf.landmarkBlockMean(first).head<3>(), Vec3::Zero());
    dup.R = Eigen::Vector3d(0.05, 0.05, 0.02).cwiseAbs2().asDiagonal();
    const long second = map->addTemplateLandmark(ekf, mirrored, dup, Vec3::Zero());
    map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), 2));
    const auto& st = map->stats();
    ASSERT_GE(st.merge_candidates, 1u);
    EXPECT_EQ(st.merged, 0u);
    EXPECT_TRUE(ekf.hasLandmark(second));
    const size_t tried = st.merge_candidates;
    // Within merge_retry_scans the pair is not tried again.
    map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), 3));
    EXPECT_EQ(map->stats().merge_candidates, tried);

    auto [map2, ekf2] = reloaded(*map, ekf, o);
    for (int k = 0; k < 3; ++k)
    {
        map->processScan(ekf, *scanAt(boxes(), Vec3::Zero(), 4 + k));
        map2->processScan(ekf2, *scanAt(boxes(), Vec3::Zero(), 4 + k));
    }
    EXPECT_EQ(map->stats().list(), map2->stats().list());
    EXPECT_EQ(ekf.mean(), ekf2.mean());
    EXPECT_EQ(Eigen::MatrixXd(ekf.cov()), Eigen::MatrixXd(ekf2.cov()));
    EXPECT_EQ(map->stats().merge_candidates, tried);
}

// wide_max_free_conflict: every template made from a scan keeps that scan's returns, the
// kept scans are part of the saved state, and without the check nothing is kept.
TEST(ScanLandmarkMap, TemplatesKeepTheirFirstScanForTheFreeSpaceCheck)
{
    ScanLandmarkMap::Options o;
    o.wide_search = true;
    o.wide_max_free_conflict = 0.2;
    auto [map, ekf] = afterFirstScan(o, 1);
    ASSERT_FALSE(map->templates().empty());
    const PointSet returns = fromScan(*scanAt(boxes(), Vec3::Zero(), 1), o.noise);
    ASSERT_EQ(map->firstScans().size(), map->templates().size());
    for (const auto& [id, scan] : map->firstScans())
    {
        EXPECT_TRUE(map->templates().count(id)) << id;
        EXPECT_EQ(scan, returns.points) << id;
    }
    auto [map2, ekf2] = reloaded(*map, ekf, o);
    EXPECT_EQ(map2->firstScans(), map->firstScans());
    ScanLandmarkMap::Options off = o;
    off.wide_max_free_conflict = 1;
    EXPECT_TRUE(afterFirstScan(off, 1).first->firstScans().empty());
}

// view_corr_share: a template's first fused alignment keeps its R; an alignment from
// (nearly) the viewpoint of an earlier fused one gets R times 1 + c (coth(delta / 2L) - 1);
// with a correlation length far below delta the factor is 1 again. The fused viewpoints
// are part of the saved state.
TEST(ScanLandmarkMap, AlignmentFromAFusedViewpointCountsAsCorrelated)
{
    ScanLandmarkMap::Options plain, corr, short_corr;
    corr.view_corr_share = short_corr.view_corr_share = 0.6;
    corr.view_corr_length_m = 5;
    short_corr.view_corr_length_m = 1e-4;
    // Plain references, not structured bindings: C++17 lambdas cannot capture those.
    auto r0 = afterFirstScan(plain, 1);
    auto r1 = afterFirstScan(corr, 1);
    auto r2 = afterFirstScan(short_corr, 1);
    auto &m0 = r0.first, &m1 = r1.first, &m2 = r2.first;
    auto &e0 = r0.second, &e1 = r1.second, &e2 = r2.second;
    ASSERT_GE(m0->stats().created, 1u);
    const Vec3 pose(0.5, 0, 0);
    auto step = [&](uint32_t seed) {
        for (auto* e : {&e0, &e1, &e2}) drive(*e, Vec3(0.5, 0, 0), 1e-4, 1e-6);
        for (auto [m, e] : {std::pair{m0.get(), &e0}, {m1.get(), &e1}, {m2.get(), &e2}})
            m->processScan(*e, *scanAt(boxes(), pose, seed));
    };
    step(2);  // first fused alignments: every R as without the option
    ASSERT_FALSE(m0->lastAligned().empty());
    ASSERT_EQ(m0->lastAligned().size(), m1->lastAligned().size());
    std::map<long, Vec2> first_view;
    for (size_t k = 0; k < m0->lastAligned().size(); ++k)
    {
        const auto& a0 = m0->lastAligned()[k];
        const auto& a1 = m1->lastAligned()[k];
        ASSERT_TRUE(a0.updated);
        EXPECT_EQ(a0.R, a1.R);
        first_view[a1.id] = inverse(a1.z).head<2>();
    }
    EXPECT_EQ(e0.mean(), e1.mean());

    auto r3 = reloaded(*m1, e1, corr);
    auto &m3 = r3.first;
    auto &e3 = r3.second;

    // Stand still and look again: the viewpoints are centimetres apart.
    mrpt::math::CMatrixDouble33 none;
    none.setZero();
    for (auto* e : {&e0, &e1, &e2, &e3})
        e->predictOdometry(mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(0, 0, 0), none));
    for (auto [m, e] : {std::pair{m0.get(), &e0}, {m1.get(), &e1}, {m2.get(), &e2}, {m3.get(), &e3}})
        m->processScan(*e, *scanAt(boxes(), pose, 3));
    ASSERT_EQ(m0->lastAligned().size(), m1->lastAligned().size());
    ASSERT_EQ(m1->lastAligned().size(), m3->lastAligned().size());
    size_t checked = 0;
    for (size_t k = 0; k < m1->lastAligned().size(); ++k)
    {
        const auto& a0 = m0->lastAligned()[k];
        const auto& a1 = m1->lastAligned()[k];
        const auto& a2 = m2->lastAligned()[k];
        EXPECT_EQ(a1.R, m3->lastAligned()[k].R);  // the reloaded map knows the viewpoints
        const auto it = first_view.find(a1.id);
        if (it == first_view.end()) continue;
        // The states (hence z_hat and z) are the same at this scan as long as the plain
        // and the correlated maps fused the same: they did at the first step, so compare
        // R / R_plain against the factor of the two viewpoints.
        const double delta = (inverse(a1.z).head<2>() - it->second).norm();
        const double f = 1.0 / std::tanh(delta / 10.0);
        const double expected = std::min(1.0 + 0.6 * (f - 1.0), ScanLandmarkMap::kMaxViewCorrFactor);
        EXPECT_LT(delta, 0.3);
        EXPECT_GT(expected, 10.0);
        for (int i = 0; i < 3; ++i)
        {
            EXPECT_NEAR(a1.R(i, i) / a0.R(i, i), expected, 1e-6 * expected);
            EXPECT_NEAR(a2.R(i, i) / a0.R(i, i), 1.0, 1e-9);  // L << delta: independent again
        }
        ++checked;
    }
    EXPECT_GE(checked, 1u);
    expectFinite(e1);
}

// view_corr_model = state: a template's first local alignment of a pass creates its
// apparent pose (an auxiliary block, not a landmark), which the update observes with
// (1 - c) R; the block stays while the viewpoint stays within view_corr_drop_lengths L,
// is marginalised out beyond, and the next pass's alignments near the earlier viewpoints
// get R scaled as in the inflate model. Blocks and viewpoints are in the saved state.
TEST(ScanLandmarkMap, StateModelObservesAnApparentPoseThatFollowsTheViewpoint)
{
    ScanLandmarkMap::Options plain, state;
    state.view_corr_share = 0.6;
    state.view_corr_length_m = 5;
    state.view_corr_model = ScanLandmarkMap::Options::ViewCorrModel::State;
    state.view_corr_drop_lengths = 0.05;  // beyond 0.25 m of viewpoint change
    auto r0 = afterFirstScan(plain, 1);
    auto r1 = afterFirstScan(state, 1);
    auto &m0 = r0.first, &m1 = r1.first;
    auto &e0 = r0.second, &e1 = r1.second;
    ASSERT_GE(m0->stats().created, 1u);
    const auto auxiliary = [](const hymm::ekf::EkfSlam& e) {
        std::vector<long> ids;
        for (const auto& b : e.layout().blocks())
            if (b.auxiliary) ids.push_back(b.id);
        return ids;
    };
    EXPECT_TRUE(auxiliary(e1).empty());
    const auto step = [&](const Vec3& pose, const Vec3& d, uint32_t seed) {
        for (auto* e : {&e0, &e1}) drive(*e, d, 1e-4, 1e-6);
        m0->processScan(e0, *scanAt(boxes(), pose, seed));
        m1->processScan(e1, *scanAt(boxes(), pose, seed));
    };
    step(Vec3(0.1, 0, 0), Vec3(0.1, 0, 0), 2);
    ASSERT_FALSE(m1->lastAligned().empty());
    ASSERT_EQ(m0->lastAligned().size(), m1->lastAligned().size());
    size_t fused = 0;
    for (size_t k = 0; k < m1->lastAligned().size(); ++k)
    {
        // Same states so far, same alignment: the update took (1 - c) of the plain R.
        const auto& a0 = m0->lastAligned()[k];
        const auto& a1 = m1->lastAligned()[k];
        ASSERT_EQ(a0.id, a1.id);
        EXPECT_LT((a1.R - 0.4 * a0.R).cwiseAbs().maxCoeff(), 1e-12 * a0.R.cwiseAbs().maxCoeff());
        fused += a1.updated;
    }
    std::map<long, std::vector<Vec2>> views;  // fused viewpoints by landmark
    const auto record = [&] {
        for (const auto& a : m1->lastAligned())
            if (a.updated) views[a.id].push_back(inverse(a.z).head<2>());
    };
    record();
    const std::vector<long> first_blocks = auxiliary(e1);
    EXPECT_EQ(first_blocks.size(), fused);
    EXPECT_EQ(e1.numLandmarks(), m1->templates().size());
    EXPECT_EQ(e1.numLandmarks() + first_blocks.size(), e1.layout().numLandmarks());

    // Standing still: the viewpoints move centimetres, the blocks stay, and a reloaded
    // map and filter continue bit for bit.
    // The same state with a ten times longer correlation length (and the same drop
    // distance): its blocks relax less over the same viewpoint change.
    ScanLandmarkMap::Options longer = state;
    longer.view_corr_length_m = 50;
    longer.view_corr_drop_lengths = 0.005;
    auto r2 = reloaded(*m1, e1, state);
    auto r3 = reloaded(*m1, e1, longer);
    auto &m2 = r2.first, &m3 = r3.first;
    auto &e2 = r2.second, &e3 = r3.second;
    step(Vec3(0.1, 0, 0), Vec3::Zero(), 3);
    for (auto [m, e] : {std::pair{m2.get(), &e2}, {m3.get(), &e3}})
    {
        drive(*e, Vec3::Zero(), 1e-4, 1e-6);
        m->processScan(*e, *scanAt(boxes(), Vec3(0.1, 0, 0), 3));
    }
    record();
    const std::vector<long> still = auxiliary(e1);  // plus those of templates fused first now
    for (long b : first_blocks) EXPECT_EQ(std::count(still.begin(), still.end(), b), 1);
    EXPECT_EQ(e1.mean(), e2.mean());
    EXPECT_EQ(Eigen::MatrixXd(e1.cov()), Eigen::MatrixXd(e2.cov()));
    ASSERT_FALSE(first_blocks.empty());
    ASSERT_TRUE(e3.hasLandmark(first_blocks.front()));
    EXPECT_NE(e1.landmarkBlockCov(first_blocks.front()), e3.landmarkBlockCov(first_blocks.front()));

    // 0.6 m on: the old blocks are marginalised out and new ones made for this pass; the
    // alignments now lie 0.6 m from the earlier viewpoints, so R is the inflate model's
    // (1 + c (coth(delta / 2L) - 1)) times the plain one, times 1 - c.
    step(Vec3(0.7, 0, 0), Vec3(0.6, 0, 0), 4);
    const std::vector<long> second_blocks = auxiliary(e1);
    ASSERT_FALSE(second_blocks.empty());
    for (long b : second_blocks) EXPECT_EQ(std::count(still.begin(), still.end(), b), 0);
    size_t checked = 0;
    for (const auto& a : m1->lastAligned())
    {
        if (!a.updated) continue;
        const auto it = std::find_if(m0->lastAligned().begin(), m0->lastAligned().end(),
                                     [&](const auto& b) { return b.id == a.id; });
        if (it == m0->lastAligned().end()) continue;
        const auto v = views.find(a.id);
        if (v == views.end()) continue;
        double delta = std::numeric_limits<double>::infinity();
        for (const Vec2& p : v->second) delta = std::min(delta, (inverse(a.z).head<2>() - p).norm());
        const double f = 1.0 + 0.6 * (1.0 / std::tanh(delta / 10.0) - 1.0);
        EXPECT_GT(delta, 0.3);
        // The filters differ by now (different R before), hence their predictions and the
        // viewpoint terms of R a little: the ratio is f within that.
        const double ratio = a.R(0, 0) / (0.4 * it->R(0, 0));
        EXPECT_GT(ratio, 0.7 * f);
        EXPECT_LT(ratio, 1.4 * f);
        ++checked;
    }
    EXPECT_GE(checked, 1u);
}

// view_corr_pass_fraction: against an earlier pass's viewpoints the state model scales R
// with the share fraction * c. The same scans into three maps that differ only in the
// fraction (1, 0.5, 0): the first pass is the same in all; on the second pass 0.6 m on,
// R over the fraction-0 map's R is 1 + fraction c (coth(delta / 2L) - 1), and 1 for 0.
// The inflate model ignores the fraction.
TEST(ScanLandmarkMap, StateModelCountsEarlierPassesWithThePassFraction)
{
    ScanLandmarkMap::Options state;
    state.view_corr_share = 0.6;
    state.view_corr_length_m = 5;
    state.view_corr_model = ScanLandmarkMap::Options::ViewCorrModel::State;
    state.view_corr_drop_lengths = 0.05;  // beyond 0.25 m of viewpoint change
    const std::vector<double> fractions{1.0, 0.5, 0.0};
    std::vector<std::pair<std::unique_ptr<ScanLandmarkMap>, hymm::ekf::EkfSlam>> runs;
    for (double fraction : fractions)
    {
        ScanLandmarkMap::Options o = state;
        o.view_corr_pass_fraction = fraction;
        runs.push_back(afterFirstScan(o, 1));
    }
    const auto step = [&](const Vec3& pose, const Vec3& d, uint32_t seed) {
        for (auto& [m, e] : runs)
        {
            drive(e, d, 1e-4, 1e-6);
            m->processScan(e, *scanAt(boxes(), pose, seed));
        }
    };
    step(Vec3(0.1, 0, 0), Vec3(0.1, 0, 0), 2);
    std::map<long, Vec2> first_view;
    for (size_t k = 0; k < runs[0].first->lastAligned().size(); ++k)
    {
        const auto& a = runs[0].first->lastAligned()[k];
        for (const auto& r : runs)
        {
            ASSERT_EQ(r.first->lastAligned().size(), runs[0].first->lastAligned().size());
            EXPECT_EQ(r.first->lastAligned()[k].R, a.R);  // no earlier pass yet
        }
        if (a.updated) first_view[a.id] = inverse(a.z).head<2>();
    }
    ASSERT_FALSE(first_view.empty());
    EXPECT_EQ(runs[0].second.mean(), runs[2].second.mean());

    step(Vec3(0.7, 0, 0), Vec3(0.6, 0, 0), 4);
    // The first alignment of the second pass: the three filters are still the same there,
    // so their R differ by the factor alone.
    const auto& zero = runs[2].first->lastAligned();
    ASSERT_FALSE(zero.empty());
    const auto& a = zero.front();
    const auto v = first_view.find(a.id);
    ASSERT_TRUE(v != first_view.end() && a.updated);
    const double delta = (inverse(a.z).head<2>() - v->second).norm();
    EXPECT_GT(delta, 0.3);
    const double excess = 1.0 / std::tanh(delta / (2 * state.view_corr_length_m)) - 1.0;
    for (size_t k = 0; k < 2; ++k)
    {
        const auto& first = runs[k].first->lastAligned().front();
        EXPECT_EQ(first.id, a.id);
        const double f = 1.0 + fractions[k] * state.view_corr_share * excess;
        EXPECT_NEAR(first.R(0, 0) / a.R(0, 0), f, 1e-9 * f);
    }

    // The fraction belongs to the state model: the inflate model's R do not depend on it.
    std::vector<std::pair<std::unique_ptr<ScanLandmarkMap>, hymm::ekf::EkfSlam>> inflate;
    for (double fraction : {1.0, 0.0})
    {
        ScanLandmarkMap::Options o = state;
        o.view_corr_model = ScanLandmarkMap::Options::ViewCorrModel::Inflate;
        o.view_corr_pass_fraction = fraction;
        inflate.push_back(afterFirstScan(o, 1));
    }
    for (const auto& [pose, d, seed] : {std::tuple{Vec3(0.1, 0, 0), Vec3(0.1, 0, 0), 2u},
                                        std::tuple{Vec3(0.7, 0, 0), Vec3(0.6, 0, 0), 4u}})
    {
        for (auto& [m, e] : inflate)
        {
            drive(e, d, 1e-4, 1e-6);
            m->processScan(e, *scanAt(boxes(), pose, seed));
        }
        ASSERT_FALSE(inflate[0].first->lastAligned().empty());
        ASSERT_EQ(inflate[0].first->lastAligned().size(), inflate[1].first->lastAligned().size());
        for (size_t k = 0; k < inflate[0].first->lastAligned().size(); ++k)
            EXPECT_EQ(inflate[0].first->lastAligned()[k].R, inflate[1].first->lastAligned()[k].R);
    }
}

}  // namespace

TEST(ScanLandmarkMap, UpdateAfterAGapIsARevisitAndPartOfTheSavedState)
{
    // Scans of the same place at 0, 1 and 2 s, then at 100 s: the landmarks made then
    // (and updated at 1 or 2 s) are revisited at 100 s (98-100 s unseen); the updates at
    // 1 and 2 s are not (below revisit_gap_s, 30 s by default). A scan without
    // a time keeps the last one. The bookkeeping survives a save and load.
    const auto scanAtTime = [](double t, uint32_t seed) {
        auto s = scanAt(boxes(), Vec3::Zero(), seed);
        s->timestamp = mrpt::Clock::fromDouble(1e9 + t);
        return s;
    };
    auto map = makeMap();
    auto ekf = makeEkf();
    for (int k = 0; k < 3; ++k) map->processScan(ekf, *scanAtTime(k, 1 + k));
    ASSERT_GE(map->stats().created, 1u);
    ASSERT_GE(map->stats().updated, 1u);
    EXPECT_TRUE(map->revisits().empty());
    auto [map2, ekf2] = reloaded(*map, ekf, map->options());
    for (auto* m : {map.get(), map2.get()})
    {
        auto& e = m == map.get() ? ekf : ekf2;
        const size_t updated = m->stats().updated;
        m->processScan(e, *scanAtTime(100, 7));
        const size_t now = m->stats().updated - updated;
        ASSERT_GE(now, 1u);
        ASSERT_EQ(m->revisits().size(), now);
        for (const auto& r : m->revisits())
        {
            EXPECT_NEAR(r.t, 100, 1e-6);
            EXPECT_GE(r.unseen_s, 98 - 1e-6);
            EXPECT_LE(r.unseen_s, r.age_s + 1e-9);
            EXPECT_LE(r.age_s, 100 + 1e-6);
            EXPECT_FALSE(r.wide);
            EXPECT_TRUE(m->templates().count(r.id));
        }
        // No time: the last one is kept, so an update now is no revisit.
        auto untimed = scanAt(boxes(), Vec3::Zero(), 8);
        untimed->timestamp = INVALID_TIMESTAMP;
        m->processScan(e, *untimed);
        EXPECT_EQ(m->revisits().size(), now);
    }
    EXPECT_EQ(map->revisits().size(), map2->revisits().size());
    // With revisit_gap_s = 0 every update at a later time counts.
    ScanLandmarkMap::Options o;
    o.revisit_gap_s = 0;
    auto every = makeMap(o);
    auto e3 = makeEkf();
    every->processScan(e3, *scanAtTime(0, 1));
    every->processScan(e3, *scanAtTime(0.5, 2));
    EXPECT_EQ(every->revisits().size(), every->stats().updated);
}
