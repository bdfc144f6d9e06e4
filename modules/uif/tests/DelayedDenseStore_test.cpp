/**
 * @file DelayedDenseStore_test.cpp
 * @brief DelayedDenseStore on a hand-built filter state: what is stored, where it is
 *        fused, the passive blocks it owns, the budget policy and the error paths.
 */
#include <hymm/core/RangeBearingModel.h>
#include <hymm/dense/HybridMetricMap.h>
#include <hymm/dense/LocalDenseMap.h>
#include <hymm/dense/PointsLayer.h>
#include <hymm/ltr/DenseCovarianceView.h>
#include <hymm/uif/DelayedDenseStore.h>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

namespace
{
using hymm::uif::DelayedDenseStore;

/** Vehicle at (5, 0, 0) and landmarks 10..13 sharing a common position error, so that
 *  everything is correlated as after a few SLAM steps. */
struct Fixture
{
    hymm::ekf::EkfSlam ekf{hymm::ekf::EkfSlam::Options()};
    std::unique_ptr<hymm::ltr::RegionPartition> partition;
    std::map<long, Eigen::Vector2d> lm{{10, {10, -5}}, {11, {10, 5}}, {12, {20, 0}}, {13, {0, 12}}};

    Fixture()
    {
        const int n = 3 + 2 * 4;
        Eigen::VectorXd x(n);
        x.head<3>() << 5, 0, 0;
        Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, 3);  // common error (dx, dy, dphi)
        std::vector<std::pair<long, int>> blocks;
        int o = 3;
        for (const auto& [id, p] : lm)
        {
            x.segment<2>(o) = p;
            G.block<2, 2>(o, 0) = 0.4 * Eigen::Matrix2d::Identity();
            blocks.emplace_back(id, 2);
            o += 2;
        }
        G.block<3, 3>(0, 0) = Eigen::Vector3d(0.4, 0.4, 0.02).asDiagonal();
        Eigen::MatrixXd P = G * G.transpose();
        P.diagonal().array() += 0.01;
        ekf.setActiveState(x, P, blocks);
        // Correlation limits 0: tryAddRegion below decides when a region appears.
        hymm::ltr::RegionPartition::Options po;
        po.conditions.min_vertex_correlation = 0.0;
        po.conditions.min_vehicle_correlation = 0.0;
        partition = std::make_unique<hymm::ltr::RegionPartition>(po);
    }

    hymm::ltr::DenseCovarianceView view() const
    {
        std::map<long, int> off;
        for (long id : ekf.landmarkIds()) off[id] = static_cast<int>(ekf.landmarkBlock(id).offset);
        return hymm::ltr::DenseCovarianceView(ekf.mean(), ekf.cov(), off, 0);
    }
};

DelayedDenseStore::Options enabled()
{
    DelayedDenseStore::Options o;
    o.enabled = true;
    return o;
}

const Eigen::Matrix2d kR = Eigen::Vector2d(0.01 * 0.01, 0.002 * 0.002).asDiagonal();
const Eigen::Vector3d kSensor(0.3, 0.0, 0.1);

/** The raw (range, bearing) a sensor at kSensor on the vehicle estimate of `ekf` measures
 *  for returns at the global positions `pts` (the scan the tests hand to the store). */
std::vector<Eigen::Vector2d> observe(const hymm::ekf::EkfSlam& ekf, const std::vector<Eigen::Vector2d>& pts)
{
    std::vector<Eigen::Vector2d> z;
    for (const auto& g : pts) z.push_back(hymm::core::observeRangeBearing(ekf.vehiclePose(), kSensor, g));
    return z;
}

TEST(DelayedDenseStoreTest, StoresReturnsInPotentialRegionsAsOnePassivePoseBlock)
{
    Fixture f;
    DelayedDenseStore store(enabled());
    const std::vector<Eigen::Vector2d> pts{{12, 0}, {13, 1}, {15, -1}, {-40, 0}};
    const auto rep = store.addScan(f.ekf, *f.partition, observe(f.ekf, pts), kR, kSensor, 1.0);
    EXPECT_EQ(rep.offered, 4u);
    EXPECT_EQ(rep.stored, 3u);
    EXPECT_EQ(rep.outside_potential, 1u);
    ASSERT_EQ(store.numStoredScans(), 1u);
    ASSERT_EQ(f.ekf.passive().numBlocks(), 1u);
    const auto& scan = store.scans().front();
    // The block is a copy of the vehicle pose: same mean, P_vv and P_v* (Eq. 2.53, G_v = I).
    EXPECT_EQ(f.ekf.passive().mean(scan.passive_id), f.ekf.vehiclePose());
    EXPECT_LT((f.ekf.passive().cov(scan.passive_id) - f.ekf.vehicleCov()).norm(), 1e-15);
    EXPECT_LT((f.ekf.passive().crossCov(scan.passive_id) - f.ekf.cov().topRows<3>()).norm(), 1e-15);
    // Each potential region meets geometry and no-overlap and holds its returns.
    ASSERT_GE(store.potentialRegions().size(), 1u);
    for (const auto& p : scan.points)
    {
        const auto& pr = store.potentialRegions().region(p.potential_region);
        const hymm::ltr::TriangleFrame tri(f.lm.at(pr.vertex_ids[0]), f.lm.at(pr.vertex_ids[1]),
                                           f.lm.at(pr.vertex_ids[2]));
        EXPECT_TRUE(tri.contains(pts.at(static_cast<size_t>(p.tag)), 1e-9));
        // The stored raw measurement reproduces the global point.
        const auto local = store.localPointEstimate(f.ekf, scan, 0, pr.vertex_ids);
        EXPECT_TRUE(local.cov.allFinite());
        EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(local.cov).eigenvalues().minCoeff(), 0.0);
    }
}

TEST(DelayedDenseStoreTest, FusesCoveredReturnsIntoTheRegionAndReleasesThePassiveBlock)
{
    for (const bool later_region : {true, false})
    {
        Fixture f;
        DelayedDenseStore store(enabled());
        const std::vector<Eigen::Vector2d> pts{{12, 0}, {13, 1}, {15, -1}};
        store.addScan(f.ekf, *f.partition, observe(f.ekf, pts), kR, kSensor, 1.0);
        // Nothing covers them yet: fuse() keeps everything.
        hymm::dense::LocalDenseMap map(0, {{f.lm[10], f.lm[11], f.lm[12]}});
        map.addLayer(std::make_unique<hymm::dense::PointsLayer>(hymm::dense::PointsLayer::Options()));
        std::vector<hymm::dense::RegionScan> received;
        const auto sink = [&](long, const hymm::dense::RegionScan& rs)
        {
            received.push_back(rs);
            map.insert(rs);
        };
        EXPECT_EQ(store.fuse(f.ekf, *f.partition, sink).fused, 0u);

        long rid = -1;
        const auto view = f.view();
        ASSERT_TRUE(f.partition->tryAddRegion({10, 11, 12}, view, later_region ? 2.0 : 1.0, &rid).accepted());
        std::vector<DelayedDenseStore::FusedPoint> fused;
        const auto rep = store.fuse(f.ekf, *f.partition, sink, &fused);
        EXPECT_EQ(rep.fused, 3u);
        EXPECT_EQ(rep.scans_released, 1u);
        EXPECT_EQ(rep.regions, std::vector<long>{rid});
        EXPECT_EQ(store.numStoredPoints(), 0u);
        EXPECT_EQ(f.ekf.passive().numBlocks(), 0u);
        EXPECT_EQ(store.potentialRegions().size(), 0u);
        EXPECT_EQ(map.layer("points")->size(), 3u);
        ASSERT_EQ(received.size(), 1u);
        // Reference == current at creation: the fused points are where they were seen.
        for (size_t i = 0; i < 3; ++i) EXPECT_LT((received[0].hits[i] - pts[i]).norm(), 1e-9);
        // The beam reaches the return, clipped to the triangle; only into a region created
        // after the scan (an older one got it at insertion time).
        EXPECT_EQ(received[0].rays.size(), later_region ? 3u : 0u);
        for (const auto& ray : received[0].rays) EXPECT_TRUE(ray.ends_at_hit);
        ASSERT_EQ(fused.size(), 3u);
        for (const auto& fp : fused)
        {
            auto ids = fp.vertex_ids;  // the partition orders vertices counter-clockwise
            std::sort(ids.begin(), ids.end());
            EXPECT_EQ(ids, (std::array<long, 3>{{10, 11, 12}}));
            EXPECT_LT((fp.local.cov - fp.local.cov.transpose()).norm(), 1e-18);
        }
    }
}

TEST(DelayedDenseStoreTest, FusedRegionScansCarryTheScanNoiseAndTheRegionMap)
{
    Fixture f;
    DelayedDenseStore store(enabled());
    store.addScan(f.ekf, *f.partition, observe(f.ekf, {{12, 0}, {13, 1}, {15, -1}}), kR, kSensor, 1.0);
    long rid = -1;
    ASSERT_TRUE(f.partition->tryAddRegion({10, 11, 12}, f.view(), 2.0, &rid).accepted());
    // An observation of landmark 12 away from its estimate moves and deforms the triangle
    // (the passive block follows through the UIF).
    hymm::ekf::RangeBearingObs o;
    o.id = 12;
    o.R = Eigen::Vector2d(0.05 * 0.05, 0.01 * 0.01).asDiagonal();
    o.z = hymm::core::observeRangeBearing(f.ekf.vehiclePose(), kSensor, f.lm[12] + Eigen::Vector2d(0.5, 0.4));
    f.ekf.updateRangeBearing({o}, mrpt::poses::CPose3D(kSensor.x(), kSensor.y(), 0, kSensor.z(), 0, 0));
    f.partition->updateVertexPositions(f.view());
    const Eigen::Matrix2d expected = f.partition->referenceToCurrent(rid).inverse().linear();
    ASSERT_GT((expected - Eigen::Matrix2d::Identity()).norm(), 1e-4) << "the region did not deform";

    std::vector<hymm::dense::RegionScan> received;
    store.fuse(f.ekf, *f.partition, [&](long, const hymm::dense::RegionScan& rs) { received.push_back(rs); });
    ASSERT_EQ(received.size(), 1u);
    // What HybridMetricMap::insertScan gives a direct scan (the SOG and particle layers
    // read them); before, a delayed scan carried 0 ("unknown") and the identity.
    EXPECT_DOUBLE_EQ(received[0].range_std_m, std::sqrt(kR(0, 0)));
    EXPECT_DOUBLE_EQ(received[0].bearing_std_rad, std::sqrt(kR(1, 1)));
    EXPECT_LT((received[0].to_reference_linear - expected).norm(), 1e-12);
}

TEST(DelayedDenseStoreTest, DelayedReturnsBecomeTheSameSogGaussiansAsDirectOnes)
{
    // The same three returns seen from the same pose: inserted directly into an existing
    // region, or stored first and fused once the region exists. The sum-of-Gaussians
    // layer must model both with the scan's noise (not its own default).
    const std::vector<Eigen::Vector2d> global{{12, 0}, {13, 1.5}, {15, -1}};
    const double sr = std::sqrt(kR(0, 0)), sb = std::sqrt(kR(1, 1));
    hymm::dense::HybridMetricMap::Options mo;
    mo.enable_occupancy = false;
    mo.enable_sog = true;
    mo.sog.range_std_m = 0.3;  // far from the scan's noise: a fallback would show
    mo.sog.bearing_std_deg = 3.0;

    Fixture direct;
    hymm::dense::HybridMetricMap direct_map(mo);
    ASSERT_TRUE(direct.partition->tryAddRegion({10, 11, 12}, direct.view(), 1.0).accepted());
    hymm::dense::ScanPoints scan;
    scan.sensor_on_vehicle = mrpt::math::TPose2D(kSensor.x(), kSensor.y(), kSensor.z());
    scan.range_std_m = sr;
    scan.bearing_std_rad = sb;
    std::vector<Eigen::Vector2d> z;
    for (const auto& g : global)
    {
        z.push_back(hymm::core::observeRangeBearing(direct.ekf.vehiclePose(), kSensor, g));
        scan.points.emplace_back(z.back().x() * std::cos(z.back().y()), z.back().x() * std::sin(z.back().y()));
    }
    const Eigen::Vector3d v = direct.ekf.vehiclePose();
    ASSERT_EQ(direct_map.insertScan(scan, mrpt::math::TPose2D(v.x(), v.y(), v.z()), *direct.partition).returns_stored, 3u);

    Fixture delayed;
    hymm::dense::HybridMetricMap delayed_map(mo);
    DelayedDenseStore store(enabled());
    ASSERT_EQ(store.addScan(delayed.ekf, *delayed.partition, z, kR, kSensor, 1.0).stored, 3u);
    long rid = -1;
    ASSERT_TRUE(delayed.partition->tryAddRegion({10, 11, 12}, delayed.view(), 2.0, &rid).accepted());
    EXPECT_EQ(store.fuse(delayed.ekf, *delayed.partition,
                         [&](long id, const hymm::dense::RegionScan& rs)
                         { delayed_map.insertRegionScan(id, rs, *delayed.partition); })
                  .fused,
              3u);

    const auto* a = direct_map.localMap(rid)->layerAs<hymm::dense::SogLayer>("sog");
    const auto* b = delayed_map.localMap(rid)->layerAs<hymm::dense::SogLayer>("sog");
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->gaussians().size(), 3u);
    ASSERT_EQ(b->gaussians().size(), 3u);
    for (size_t i = 0; i < 3; ++i)
    {
        EXPECT_LT((a->gaussians()[i].mean - b->gaussians()[i].mean).norm(), 1e-9);
        EXPECT_LT((a->gaussians()[i].cov - b->gaussians()[i].cov).norm(), 1e-12);
        // The scan's 1 cm range noise, not the layer's 0.3 m: the along-beam variance.
        const Eigen::Vector2d along = (global[i] - Eigen::Vector2d(5.3, 0.0)).normalized();
        EXPECT_NEAR(along.dot(b->gaussians()[i].cov * along), sr * sr, 0.2 * sr * sr);
    }
}

TEST(DelayedDenseStoreTest, ReturnsAlreadyInARegionOrOutsidePotentialRegionsCanWait)
{
    // A region created after the caller assigned the returns (e.g. from a virtual apex):
    // its returns wait for the next fuse() instead of being discarded.
    Fixture f;
    ASSERT_TRUE(f.partition->tryAddRegion({10, 11, 12}, f.view(), 1.0).accepted());
    DelayedDenseStore store(enabled());
    const std::vector<Eigen::Vector2d> pts{{12, 0}, {-40, 0}};
    auto rep = store.addScan(f.ekf, *f.partition, observe(f.ekf, pts), kR, kSensor, 1.0);
    EXPECT_EQ(rep.stored, 1u);
    EXPECT_EQ(rep.in_region, 1u);
    EXPECT_EQ(rep.outside_potential, 1u);  // (-40, 0): no landmark triangle near it
    EXPECT_EQ(store.fuse(f.ekf, *f.partition, [](long, const hymm::dense::RegionScan&) {}).fused, 1u);

    // Without the potential-region condition every return in no region waits.
    auto o = enabled();
    o.require_potential_region = false;
    DelayedDenseStore all(o);
    Fixture g;
    rep = all.addScan(g.ekf, *g.partition, observe(g.ekf, pts), kR, kSensor, 1.0);
    EXPECT_EQ(rep.stored, 2u);
    EXPECT_EQ(rep.without_potential, 2u);
    EXPECT_EQ(rep.outside_potential, 0u);
    EXPECT_EQ(all.potentialRegions().size(), 0u);
    for (const auto& p : all.scans().front().points) EXPECT_EQ(p.potential_region, -1);
}

TEST(DelayedDenseStoreTest, ReturnsInNoRegionGoToTheOutsideSinkWhenItTakesThem)
{
    // No region when seen: both wait. Once a region exists, (12, 0) is fused into it and
    // (-40, 0), in no region, is offered to the outside sink at its current estimate
    // with the sensor's position; taken, it leaves the store and the scan its block.
    auto o = enabled();
    o.require_potential_region = false;
    DelayedDenseStore store(o);
    Fixture f;
    const std::vector<Eigen::Vector2d> pts{{12, 0}, {-40, 0}};
    ASSERT_EQ(store.addScan(f.ekf, *f.partition, observe(f.ekf, pts), kR, kSensor, 1.0).stored, 2u);
    const auto noop = [](long, const hymm::dense::RegionScan&) {};
    // A sink that refuses leaves it waiting.
    size_t offered = 0;
    auto rep = store.fuse(f.ekf, *f.partition, noop, nullptr,
                          [&](const Eigen::Vector2d&, const Eigen::Vector2d&) { return ++offered, false; });
    EXPECT_EQ(offered, 2u);
    EXPECT_EQ(rep.fused_outside, 0u);
    EXPECT_EQ(store.numStoredPoints(), 2u);

    ASSERT_TRUE(f.partition->tryAddRegion({10, 11, 12}, f.view(), 2.0).accepted());
    std::vector<Eigen::Vector2d> taken, sensors;
    rep = store.fuse(f.ekf, *f.partition, noop, nullptr, [&](const Eigen::Vector2d& s, const Eigen::Vector2d& r) {
        sensors.push_back(s);
        taken.push_back(r);
        return true;
    });
    EXPECT_EQ(rep.fused, 1u);
    EXPECT_EQ(rep.fused_outside, 1u);
    ASSERT_EQ(taken.size(), 1u);
    EXPECT_LT((taken[0] - Eigen::Vector2d(-40, 0)).norm(), 1e-9);  // no update since: as seen
    EXPECT_LT((sensors[0] - Eigen::Vector2d(5.3, 0)).norm(), 1e-9);
    EXPECT_EQ(store.numStoredPoints(), 0u);
    EXPECT_EQ(rep.scans_released, 1u);
    EXPECT_EQ(f.ekf.passive().numBlocks(), 0u);
}

TEST(DelayedDenseStoreTest, BudgetDropsOldestScansFirstAndThinsOversizedScans)
{
    Fixture f;
    auto o = enabled();
    o.max_stored_scans = 3;
    o.max_stored_points = 10;
    DelayedDenseStore store(o);
    const std::vector<Eigen::Vector2d> four{{12, 0}, {13, 1}, {15, -1}, {14, 0.5}};
    for (int k = 0; k < 5; ++k) store.addScan(f.ekf, *f.partition, observe(f.ekf, four), kR, kSensor, k);
    // 4 returns per scan, 10 at most: two scans fit; the newest two are kept.
    ASSERT_EQ(store.numStoredScans(), 2u);
    EXPECT_EQ(store.scans()[0].scan_id, 3);
    EXPECT_EQ(store.scans()[1].scan_id, 4);
    EXPECT_EQ(f.ekf.passive().numBlocks(), 2u);
    for (const auto& s : store.scans()) EXPECT_TRUE(f.ekf.passive().has(s.passive_id));

    std::vector<Eigen::Vector2d> many;
    for (int i = 0; i < 25; ++i) many.emplace_back(12 + 0.2 * i, 0.1 * (i % 3));
    const auto rep = store.addScan(f.ekf, *f.partition, observe(f.ekf, many), kR, kSensor, 6);
    EXPECT_EQ(rep.thinned, 15u);
    EXPECT_EQ(rep.stored, 10u);
    EXPECT_EQ(rep.evicted_scans, 2u);
    EXPECT_EQ(store.numStoredPoints(), 10u);
    EXPECT_EQ(f.ekf.passive().numBlocks(), 1u);

    auto aged = enabled();
    aged.max_age_s = 2.5;
    DelayedDenseStore young(aged);
    Fixture g;
    for (int k = 0; k < 6; ++k) young.addScan(g.ekf, *g.partition, observe(g.ekf, four), kR, kSensor, k);
    EXPECT_EQ(young.scans().front().time, 3.0);
    EXPECT_EQ(g.ekf.passive().numBlocks(), young.numStoredScans());
}

TEST(DelayedDenseStoreTest, DisabledStoreLeavesTheFilterAlone)
{
    Fixture f;
    DelayedDenseStore store{DelayedDenseStore::Options()};
    const auto rep = store.addScan(f.ekf, *f.partition, observe(f.ekf, {{12, 0}}), kR, kSensor, 1.0);
    EXPECT_EQ(rep.offered, 1u);
    EXPECT_EQ(rep.stored, 0u);
    EXPECT_EQ(f.ekf.passive().numBlocks(), 0u);
    EXPECT_EQ(store.fuse(f.ekf, *f.partition, [](long, const hymm::dense::RegionScan&) {}).fused, 0u);
}

TEST(DelayedDenseStoreTest, ScansWhosePassiveBlockVanishedAreDropped)
{
    Fixture f;
    DelayedDenseStore store(enabled());
    store.addScan(f.ekf, *f.partition, observe(f.ekf, {{12, 0}, {13, 1}}), kR, kSensor, 1.0);
    ASSERT_EQ(store.numStoredPoints(), 2u);
    const Eigen::VectorXd x = f.ekf.mean();
    const Eigen::MatrixXd P = f.ekf.cov();
    std::vector<std::pair<long, int>> blocks;
    for (long id : f.ekf.landmarkIds()) blocks.emplace_back(id, 2);
    f.ekf.setActiveState(x, P, blocks);  // drops passive blocks, as reset() does
    const auto rep = store.fuse(f.ekf, *f.partition, [](long, const hymm::dense::RegionScan&) {});
    EXPECT_EQ(rep.lost_points, 2u);
    EXPECT_EQ(store.numStoredPoints(), 0u);
    EXPECT_EQ(store.numStoredScans(), 0u);
}

TEST(DelayedDenseStoreTest, InvalidInputsGiveClearErrors)
{
    Fixture f;
    DelayedDenseStore store(enabled());
    const std::vector<Eigen::Vector2d> z{{5, 0.1}};
    EXPECT_THROW(store.addScan(f.ekf, *f.partition, z, Eigen::Matrix2d::Zero(), kSensor, 1.0), std::invalid_argument);
    const std::vector<long> tags{1, 2};
    EXPECT_THROW(store.addScan(f.ekf, *f.partition, z, kR, kSensor, 1.0, &tags), std::invalid_argument);
    store.addScan(f.ekf, *f.partition, z, kR, kSensor, 2.0);
    EXPECT_THROW(store.addScan(f.ekf, *f.partition, z, kR, kSensor, 1.0), std::invalid_argument);
    // Non-finite or non-positive ranges are skipped, not stored.
    const std::vector<Eigen::Vector2d> bad{{std::nan(""), 0.0}, {-1.0, 0.0}};
    EXPECT_EQ(store.addScan(f.ekf, *f.partition, bad, kR, kSensor, 3.0).stored, 0u);
    ASSERT_EQ(store.numStoredScans(), 1u);
    EXPECT_THROW(store.localPointEstimate(f.ekf, store.scans().front(), 0, {{10, 11, 99}}), std::invalid_argument);
    EXPECT_THROW(store.localPointEstimate(f.ekf, store.scans().front(), 7, {{10, 11, 12}}), std::out_of_range);
}

}  // namespace
