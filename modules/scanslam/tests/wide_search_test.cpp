// The wide search of a re-observation after drift (WideSearch.h, ScanLandmarkMap::observeWide):
// the true pose found from a prediction metres and > 10 deg off, a corridor (slides along
// itself) refused as ambiguous, a drifted filter pulled back by a loop closure, an answer
// held until another template agrees, and the window cut to the template's viewpoints.
#include <gtest/gtest.h>
#include <hymm/scanslam/ScanLandmarkMap.h>
#include <hymm/scanslam/Segmenter.h>
#include <hymm/scanslam/WideSearch.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/random/RandomGenerators.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "sim_scenes.h"

namespace
{
using namespace hymm::scanslam;
using namespace hymm::scanslam::testing;

const double kDeg = M_PI / 180;

/** An asymmetric pentagon (faces 7, 2, 4.2, 5 and 3 m) (the target) and a thin wall. Other convex objects nearby
 *  (boxes, triangles) offer corners that a partial view of the pentagon fits almost as
 *  well: that is a real ambiguity (refused), not the case tested here. */
hymm::sim::World scene()
{
    std::vector<hymm::sim::WorldObject> objs;
    objs.push_back(fixedObject(0, {{-3, -2}, {4, -2}, {4, 0}, {1, 3}, {-3, 1}}, 12, 4, 0.3));
    objs.push_back(fixedObject(2, box(5, 0.2), 20, -1, -0.3));
    return hymm::sim::World({}, std::move(objs));
}

/** The template of the largest segment within 4 m of `near` in a scan from `pose`
 *  (Table 5.1 laser). */
ScanTemplate templateNear(const hymm::sim::World& w, const Vec3& pose, const Vec2& near, uint32_t seed,
                          std::vector<Vec2>* scan = nullptr)
{
    const PointSet s = simulate(w, pose, seed, Laser{0.1, 1.0, 30, 0.5});
    if (scan) *scan = s.points;
    Segmenter::Options so;
    so.min_points = 10;
    const auto segs = Segmenter(so).segment(s);
    ScanTemplate best;
    for (const auto& seg : segs)
    {
        ScanTemplate t = ScanTemplate::fromSegment(s, seg);
        const double d = (transformPoint(pose, t.frame_in_sensor.head<2>()) - near).norm();
        if (d < 4 && t.sog.size() > best.sog.size()) best = t;
    }
    return best;
}

/** A Table 5.1 scan (30 m, 0.5 deg) from `pose` (the origin by default), as the laser
 *  delivers it. */
mrpt::obs::CObservation2DRangeScan::Ptr scanAtOrigin(const hymm::sim::World& w, uint32_t seed,
                                                     const Vec3& pose = Vec3::Zero())
{
    hymm::sim::LaserSimulator::Options lo;
    lo.max_range_m = 30, lo.fov = M_PI, lo.resolution = 0.5 * kDeg, lo.std_range_m = 0.1, lo.std_bearing = kDeg;
    return hymm::sim::LaserSimulator(lo, seed, seed + 1000).observe(w, pose, 0.0, mrpt::Clock::now());
}

/** The template of the object near `near` in a scan from the origin, added as a landmark
 *  seen from the origin (frame std 0.1 m, 1 deg). */
void addTemplateNear(ScanLandmarkMap& map, hymm::ekf::EkfSlam& ekf, const hymm::sim::World& w, const Vec2& near)
{
    std::vector<Vec2> scan;
    const ScanTemplate tpl = templateNear(w, Vec3::Zero(), near, 1, &scan);
    EXPECT_GE(tpl.sog.size(), 10u);
    AlignResult made;
    made.ok = true;
    made.z = tpl.frame_in_sensor;
    made.R = Vec3(0.01, 0.01, kDeg * kDeg).asDiagonal();
    map.addTemplateLandmark(ekf, tpl, made, Vec3::Zero(), scan);
}

/** The odometry's belief that the vehicle moved by `u`, with std std_xy [m], std_phi [rad]. */
void believeMove(hymm::ekf::EkfSlam& ekf, const Vec3& u, double std_xy, double std_phi)
{
    mrpt::math::CMatrixDouble33 c;
    c.setZero();
    c(0, 0) = c(1, 1) = std_xy * std_xy;
    c(2, 2) = std_phi * std_phi;
    ekf.predictOdometry(mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(u.x(), u.y(), u.z()), c));
}

TEST(ScanWideSearch, FindsTheTruePoseFromAPredictionMetresOff)
{
    const auto w = scene();
    const Vec3 a(0, 0, 0), b(3, 1, 0.15);
    const Vec3 drift[] = {{4, -3, 12 * kDeg}, {-5, 2, -15 * kDeg}, {3, 4, 20 * kDeg}};
    for (uint32_t k = 0; k < 3; ++k)
    {
        const ScanTemplate tpl = templateNear(w, a, Vec2(12, 4), 10 + k);
        ASSERT_GE(tpl.sog.size(), 10u);
        const PointSet scan = simulate(w, b, 40 + k, Laser{0.1, 1.0, 30, 0.5});
        const Vec3 truth = compose(inverse(b), compose(a, tpl.frame_in_sensor));
        const Vec3 half(12, 12, 30 * kDeg);
        const WideResult r = wideSearch(tpl.sog, scan, truth + drift[k], half, WideSearchOptions{});
        ASSERT_TRUE(r.ok) << "seed " << k << ": " << r.failure << " goodness " << r.goodness << " second " << r.second;
        // Inside the local matcher's basin (1 m, 15 deg), and the matcher refines it.
        EXPECT_LT((r.z.head<2>() - truth.head<2>()).norm(), 0.5) << k;
        EXPECT_LT(std::abs(mrpt::math::wrapToPi(r.z.z() - truth.z())), 8 * kDeg) << k;
        const AlignResult al = makeMatcher("sog")->align(tpl.sog, scan, r.z);
        ASSERT_TRUE(al.ok) << al.failure;
        EXPECT_LT((al.z.head<2>() - truth.head<2>()).norm(), 0.3) << k;
        EXPECT_LT(std::abs(mrpt::math::wrapToPi(al.z.z() - truth.z())), 3 * kDeg) << k;
        EXPECT_LT(r.second, 0.85 * r.goodness);
        EXPECT_GE(r.matched_fraction, 0.7);
    }
}

TEST(ScanWideSearch, CorridorIsRefusedAsAmbiguous)
{
    // Two long parallel walls: a piece of the corridor fits anywhere along it.
    std::vector<hymm::sim::WorldObject> objs;
    objs.push_back(fixedObject(0, box(80, 0.2), 20, 3, 0));
    objs.push_back(fixedObject(1, box(80, 0.2), 20, -3, 0));
    const hymm::sim::World w({}, std::move(objs));
    const PointSet s = simulate(w, Vec3::Zero(), 3, Laser{0.1, 1.0, 30, 0.5});
    PointSet piece;
    for (size_t i = 0; i < s.size(); ++i)
        if (s.points[i].x() > 6 && s.points[i].x() < 16) piece.add(s.points[i], s.covs[i]);
    const ScanTemplate tpl = ScanTemplate::fromPoints(piece);
    const Vec3 b(2, 0, 0);
    const PointSet scan = simulate(w, b, 4, Laser{0.1, 1.0, 30, 0.5});
    const Vec3 truth = compose(inverse(b), tpl.frame_in_sensor);
    const WideResult r = wideSearch(tpl.sog, scan, truth + Vec3(3, 0.5, 5 * kDeg), Vec3(8, 2, 15 * kDeg),
                                    WideSearchOptions{});
    EXPECT_FALSE(r.ok);
    EXPECT_STREQ(r.failure, "ambiguous");
    EXPECT_GT(r.second, 0.85 * r.goodness);
}

/** Options of the drift tests: wide search from 1 m of predicted std, no creation. */
ScanLandmarkMap::Options driftOptions(double view_window_m, size_t confirm_scans)
{
    ScanLandmarkMap::Options o;
    o.noise = {0.1, 1.0 * kDeg};
    o.max_prediction_std_m = 1.0;
    o.wide_search = true;
    o.wide_confirm_scans = confirm_scans;
    o.wide_view_window_m = view_window_m;
    o.create_landmarks = false;
    return o;
}

struct DriftRun
{
    std::vector<std::map<std::string, size_t>> wide;  //!< outcomes after each scan
    Vec3 x = Vec3::Zero();                            //!< vehicle pose at the end
    bool cov_finite = false;                          //!< the filter's covariance at the end
    Mat3 P = Mat3::Zero();                            //!< the vehicle's covariance at the end
    std::vector<Mat3> wide_R;                         //!< R of each wide answer, as fused
};

/** What the odometry believes after the templates were made: a move `move` with std
 *  std_xy [m], std_phi [rad] (by default a 4 m move that did not happen); the scans
 *  that follow are taken from `scan_pose` with seeds first_seed, first_seed + 1, ... */
struct Drift
{
    Vec3 move = Vec3(4, 0.5, 0.05);
    double std_xy = 3;
    double std_phi = 8 * kDeg;
    Vec3 scan_pose = Vec3::Zero();
    uint32_t first_seed = 7;
};

/** A filter at the origin holding the templates of the objects near `near` (scan from
 *  the origin) as landmarks; the odometry then believes `drift`; `scans` scans follow. */
DriftRun closeAfterDrift(const hymm::sim::World& w, const std::vector<Vec2>& near,
                         const ScanLandmarkMap::Options& o, uint32_t scans, const Drift& drift = {})
{
    ScanLandmarkMap map(o, Segmenter::Options{}, SegmentAcceptance::Options{}, makeMatcher("sog"));
    hymm::ekf::EkfSlam ekf{hymm::ekf::EkfSlam::Options{}};
    ekf.reset(Vec3::Zero(), 1e-6 * Mat3::Identity());
    for (const Vec2& p : near) addTemplateNear(map, ekf, w, p);
    believeMove(ekf, drift.move, drift.std_xy, drift.std_phi);
    DriftRun run;
    for (uint32_t k = 0; k < scans; ++k)
    {
        map.processScan(ekf, *scanAtOrigin(w, drift.first_seed + k, drift.scan_pose));
        run.wide.push_back(map.stats().wide);
        for (const auto& a : map.lastAligned())
            if (a.wide) run.wide_R.push_back(a.R);
    }
    run.x = ekf.vehiclePose();
    run.cov_finite = ekf.cov().allFinite();
    run.P = ekf.cov().topLeftCorner<3, 3>();
    return run;
}

/** The default drift with the odometry's position std `std_xy` [m]. */
Drift driftWithStd(double std_xy)
{
    Drift d;
    d.std_xy = std_xy;
    return d;
}

size_t count(const std::map<std::string, size_t>& m, const char* k) { return m.count(k) ? m.at(k) : 0; }

std::string str(const std::map<std::string, size_t>& m)
{
    std::string out;
    for (const auto& [k, n] : m) out += k + "=" + std::to_string(n) + " ";
    return out;
}

/** Odometry believes the vehicle moved 3.6 m and 11.5 deg (std 3 m, 12 deg): it did not.
 *  One template in the scene (the pentagon): nothing to confirm with. */
DriftRun closeOneTemplate(const ScanLandmarkMap::Options& o)
{
    Drift drift;
    drift.move = Vec3(3, -2, 0.2);
    drift.std_phi = 12 * kDeg;
    drift.first_seed = 2;
    return closeAfterDrift(scene(), {Vec2(12, 4)}, o, 1, drift);
}

TEST(ScanWideSearch, ClosesTheLoopOfADriftedFilter)
{
    const DriftRun run = closeOneTemplate(driftOptions(0, 0));
    EXPECT_EQ(count(run.wide[0], "closed"), 1u) << str(run.wide[0]);
    EXPECT_LT(run.x.head<2>().norm(), 1.0) << run.x.transpose();
    EXPECT_LT(std::abs(run.x.z()), 2 * kDeg) << run.x.transpose();
    EXPECT_TRUE(run.cov_finite);
}

TEST(ScanWideSearch, CovarianceInflationScalesTheWideAnswersR)
{
    // The same closure as above with the wide answer's R times 4: the same answer (same
    // scan, same search) is fused with 4 R, so the vehicle keeps more of its uncertainty
    // and moves less of the way in this one update.
    const DriftRun plain = closeOneTemplate(driftOptions(0, 0));
    ScanLandmarkMap::Options o = driftOptions(0, 0);
    o.wide_cov_inflation = 4;
    const DriftRun inflated = closeOneTemplate(o);
    ASSERT_EQ(plain.wide_R.size(), 1u);
    ASSERT_EQ(inflated.wide_R.size(), 1u);
    EXPECT_TRUE(inflated.wide_R[0].isApprox(4 * plain.wide_R[0], 1e-9))
        << plain.wide_R[0] << "\n" << inflated.wide_R[0];
    EXPECT_EQ(count(inflated.wide[0], "closed"), 1u) << str(inflated.wide[0]);
    EXPECT_GT(inflated.P.trace(), plain.P.trace());
    EXPECT_GT(inflated.P(2, 2), plain.P(2, 2));
    // The drift believed was (3, -2, 0.2): the vehicle ends nearer to it.
    EXPECT_GT(inflated.x.head<2>().norm(), plain.x.head<2>().norm());
    EXPECT_TRUE(inflated.cov_finite);
}

TEST(ScanWideSearch, AnswerWaitsForTheAgreementOfOtherTemplates)
{
    // Two quadrilaterals, each found alone (fused at once without the confirmation),
    // searched one per scan: the first answer waits (pending) until the other template's
    // answer implies the same vehicle correction; only then is one fused.
    std::vector<hymm::sim::WorldObject> objs;
    objs.push_back(fixedObject(0, {{-2, -2}, {5, -1}, {0, 1}, {-2, 3}}, 11, 8, 0.8));
    objs.push_back(fixedObject(1, {{-2, -2}, {5, -1}, {0, 1}, {-2, 3}}, 15, -8, -1.0));
    const hymm::sim::World w({}, std::move(objs));
    const std::vector<Vec2> near{{11, 8}, {15, -8}};
    for (const Vec2& p : near)
        EXPECT_EQ(count(closeAfterDrift(w, {p}, driftOptions(0, 0), 1).wide[0], "closed"), 1u) << p.transpose();
    const DriftRun two = closeAfterDrift(w, near, driftOptions(0, 10), 8);
    const auto& end = two.wide.back();
    EXPECT_EQ(count(end, "closed"), 1u) << str(end);
    size_t first_pending = two.wide.size();
    for (size_t k = 0; k < two.wide.size(); ++k)
    {
        EXPECT_EQ(count(two.wide[k], "closed"), count(two.wide[k], "confirmed")) << k << ": " << str(two.wide[k]);
        if (first_pending == two.wide.size() && count(two.wide[k], "pending") > 0) first_pending = k;
    }
    ASSERT_LT(first_pending, two.wide.size()) << str(end);
    EXPECT_EQ(count(two.wide[first_pending], "closed"), 0u) << str(two.wide[first_pending]);
    EXPECT_LT(two.x.head<2>().norm(), 0.5) << two.x.transpose();
    // One template alone, searched again after wide_retry_scans: its own answers agree
    // with each other, but they never confirm themselves.
    const DriftRun one = closeAfterDrift(w, {near[0]}, driftOptions(0, 10), 8);
    EXPECT_GE(count(one.wide.back(), "pending"), 2u) << str(one.wide.back());
    EXPECT_EQ(count(one.wide.back(), "closed"), 0u) << str(one.wide.back());
}

TEST(ScanWideSearch, ViewWindowSearchesAVeryUncertainPredictionWhereTheTemplateWasSeen)
{
    // Odometry std 20 m: the +-3 sigma window (60 m) is refused as too large; cut to the
    // poses within 5 m of where the template was made, it is searched and the loop closes.
    std::vector<hymm::sim::WorldObject> objs;
    objs.push_back(fixedObject(0, {{-2, -2}, {5, -1}, {0, 1}, {-2, 3}}, 11, 8, 0.8));
    const hymm::sim::World w({}, std::move(objs));
    const DriftRun wide = closeAfterDrift(w, {{11, 8}}, driftOptions(0, 0), 1, driftWithStd(20));
    EXPECT_EQ(count(wide.wide[0], "window_too_large"), 1u) << str(wide.wide[0]);
    EXPECT_EQ(count(wide.wide[0], "closed"), 0u) << str(wide.wide[0]);
    const DriftRun cut = closeAfterDrift(w, {{11, 8}}, driftOptions(5, 0), 1, driftWithStd(20));
    EXPECT_EQ(count(cut.wide[0], "closed"), 1u) << str(cut.wide[0]);
    EXPECT_LT(cut.x.head<2>().norm(), 0.5) << cut.x.transpose();
    EXPECT_LT(std::abs(cut.x.z()), 2 * kDeg) << cut.x.transpose();
}

TEST(ScanWideSearch, ViewWindowRefusesAViewpointFarFromTheTemplates)
{
    // The vehicle backs 10 m away from where the template was made and knows it (std
    // 1.5 m: above max_prediction_std_m, so searched wide): its +-3 sigma window lies
    // 10 m from the template's viewpoint, beyond the 5 m cut, and is not searched.
    std::vector<hymm::sim::WorldObject> objs;
    objs.push_back(fixedObject(0, {{-2, -2}, {5, -1}, {0, 1}, {-2, 3}}, 11, 8, 0.8));
    const hymm::sim::World w({}, std::move(objs));
    Drift back;
    back.move = back.scan_pose = Vec3(-10, 0, 0);
    back.std_xy = 1.5;
    back.std_phi = kDeg;
    back.first_seed = 3;
    const auto wide = closeAfterDrift(w, {{11, 8}}, driftOptions(5, 0), 1, back).wide[0];
    EXPECT_EQ(count(wide, "view_elsewhere"), 1u) << str(wide);
    EXPECT_EQ(count(wide, "closed"), 0u) << str(wide);
}

TEST(FreeSpaceConflict, ARevisitAgreesWithItsFirstScanAndAWrongPoseDoesNot)
{
    // 20 pairs of scans of a room 0.5-2 m and up to 15 deg apart (Table 5.1 laser): at
    // their true relative pose almost no return lies in the other's free space; moved
    // 2.5 m (the other way round when the first pose is behind) or turned 20 deg, a
    // large share does.
    const auto w = room();
    mrpt::random::CRandomGenerator rng(5);
    const Laser laser{0.1, 1.0, 30, 0.5};
    double worst_true = 0, best_wrong = 1;
    for (uint32_t k = 0; k < 20; ++k)
    {
        const Vec3 a(rng.drawUniform(-3, 3), rng.drawUniform(-4, 4), rng.drawUniform(-0.4, 0.4));
        const Vec3 rel(rng.drawUniform(0.5, 2), rng.drawUniform(-1, 1), rng.drawUniform(-15, 15) * kDeg);
        const Vec3 b = compose(a, rel);
        const PointSet sa = simulate(w, a, 100 + k, laser), sb = simulate(w, b, 200 + k, laser);
        const FreeSpaceConflict truth = freeSpaceConflict(sa.points, sb.points, rel, 0.5, kDeg);
        EXPECT_GT(truth.tested_ab, 100u) << k;
        EXPECT_GT(truth.tested_ba, 100u) << k;
        worst_true = std::max(worst_true, truth.share(20));
        for (const Vec3& wrong : {compose(rel, Vec3(2.5, 0, 0)), compose(rel, Vec3(-2.5, 0, 0)),
                                  compose(rel, Vec3(0, 0, 20 * kDeg)), compose(rel, Vec3(0, 0, -20 * kDeg))})
            best_wrong = std::min(best_wrong, freeSpaceConflict(sa.points, sb.points, wrong, 0.5, kDeg).share(20));
    }
    std::cout << "conflict share: worst at the true pose " << worst_true << ", best at a wrong one " << best_wrong
              << "\n";
    EXPECT_LT(worst_true, 0.05);
    EXPECT_GT(best_wrong, 0.2);
}

TEST(FreeSpaceConflict, BearingsWithoutAReturnAreNotTested)
{
    // One wall ahead: a scan turned 180 deg looks where the other saw nothing (no
    // return is no evidence of free space), so nothing is tested and the share is 0.
    std::vector<hymm::sim::WorldObject> objs;
    objs.push_back(fixedObject(0, box(0.3, 20), 8, 0, 0));
    const hymm::sim::World w({}, std::move(objs));
    const PointSet s = simulate(w, Vec3::Zero(), 1, Laser{0.1, 1.0, 30, 0.5});
    ASSERT_GT(s.size(), 100u);
    const FreeSpaceConflict c = freeSpaceConflict(s.points, s.points, Vec3(0, 0, M_PI), 0.5, kDeg);
    EXPECT_EQ(c.tested_ab, 0u);
    EXPECT_EQ(c.tested_ba, 0u);
    EXPECT_EQ(c.share(20), 0.0);
    // The same scan at its own pose: every return tested, none in front of itself.
    const FreeSpaceConflict same = freeSpaceConflict(s.points, s.points, Vec3::Zero(), 0.5, kDeg);
    EXPECT_GE(same.tested_ab + 2, s.size());  // the bins at either end lack a neighbour
    EXPECT_EQ(same.conflicts_ab + same.conflicts_ba, 0u);
    // Too few returns tested say nothing.
    FreeSpaceConflict few;
    few.tested_ab = 5, few.conflicts_ab = 5;
    EXPECT_EQ(few.share(20), 0.0);
    EXPECT_EQ(few.share(5), 1.0);
}

TEST(ScanWideSearch, LookalikeIsRefusedByTheFreeSpaceOfTheTemplatesFirstScan)
{
    // Two copies of the pentagon 40 m apart (beyond the laser's 30 m from each other's
    // place), in places that differ: walls 15 m above and 23 m right of the first, 10 m
    // below and 12 m right of the second. The template is made of the first copy, seen
    // from the origin. The vehicle is in fact 40 m lower, where it sees the second copy
    // exactly as the first was seen, while odometry believes it near the origin. The
    // wide search finds the copy: a lookalike answer, closed at once without the check
    // and refused with it, since the scan's near walls lie where the first scan saw
    // through to its far ones. 11 noise draws each.
    std::vector<hymm::sim::WorldObject> objs;
    objs.push_back(fixedObject(0, {{-3, -2}, {4, -2}, {4, 0}, {1, 3}, {-3, 1}}, 12, 5, 0.3));
    objs.push_back(fixedObject(1, {{-3, -2}, {4, -2}, {4, 0}, {1, 3}, {-3, 1}}, 12, -35, 0.3));
    objs.push_back(fixedObject(2, box(40, 0.2), 15, 20, 0));
    objs.push_back(fixedObject(3, box(0.2, 24), 28, 2, 0));
    objs.push_back(fixedObject(4, box(0.2, 30), 24, -45, 0));
    objs.push_back(fixedObject(5, box(40, 0.2), 15, -50, 0));
    const hymm::sim::World w({}, std::move(objs));
    for (uint32_t seed = 1; seed <= 11; ++seed)
    {
        Drift drift;
        drift.move = Vec3(2, 0.5, 0.05);
        drift.scan_pose = Vec3(0, -40, 0);
        drift.first_seed = seed;
        ScanLandmarkMap::Options o = driftOptions(0, 0);
        const DriftRun fooled = closeAfterDrift(w, {{12, 5}}, o, 1, drift);
        EXPECT_EQ(count(fooled.wide[0], "closed"), 1u) << seed << ": " << str(fooled.wide[0]);
        EXPECT_LT(fooled.x.head<2>().norm(), 1.0) << fooled.x.transpose();  // where it is not
        o.wide_max_free_conflict = 0.1;
        const DriftRun checked = closeAfterDrift(w, {{12, 5}}, o, 1, drift);
        EXPECT_EQ(count(checked.wide[0], "free_space_conflict"), 1u) << seed << ": " << str(checked.wide[0]);
        EXPECT_EQ(count(checked.wide[0], "closed"), 0u) << seed << ": " << str(checked.wide[0]);
        // The true revisit (the vehicle at odometry's origin) still closes with it.
        drift.scan_pose = Vec3::Zero();
        const DriftRun revisit = closeAfterDrift(w, {{12, 5}}, o, 1, drift);
        EXPECT_EQ(count(revisit.wide[0], "closed"), 1u) << seed << ": " << str(revisit.wide[0]);
        EXPECT_LT(revisit.x.head<2>().norm(), 0.5) << seed << ": " << revisit.x.transpose();
    }
}

}  // namespace
