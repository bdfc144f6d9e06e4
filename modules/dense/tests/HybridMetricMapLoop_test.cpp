/**
 * @file HybridMetricMapLoop_test.cpp
 * @brief Example 3.2 behaviour: after the landmark estimates move (a loop closure), the
 *        rendered dense map moves with the triangles while stored content is unchanged.
 */
#include "hymm/dense/HybridMetricMap.h"

#include "hymm/dense/outline_metrics.h"
#include "synthetic_partition.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace
{
using namespace hymm::dense;
using namespace hymm::dense::synthetic;
using V2 = Eigen::Vector2d;

const mrpt::math::TPose2D kVehicle{3.0, 7.5, 0.0};

struct Fixture
{
    Lattice lattice{5, 4, 5.0, V2(0, 0)};
    hymm::ltr::DenseCovarianceView view = makeDenseView(lattice.landmarks(), Eigen::Vector3d(3, 7.5, 0));
    hymm::ltr::RegionPartition partition{permissivePartitionOptions()};
    HybridMetricMap map{[] {
        HybridMetricMap::Options o;
        o.occupancy.cell_size_m = 0.1;
        return o;
    }()};

    Fixture()
    {
        addRegions(partition, view, lattice.triangles(V2(10, 7.5)), 24);
        const ScanPoints scan = wallScan(kVehicle, {0.3, 0, 0}, 17.0, 161, 40.0 * M_PI / 180.0);
        for (int k = 0; k < 3; ++k) map.insertScan(scan, kVehicle, partition);
    }
    std::string content() const
    {
        std::stringstream ss;
        map.save(ss);
        return ss.str();
    }
    /** Applies `f` to every landmark mean and refreshes the partition. */
    template <class F>
    void moveLandmarks(F f)
    {
        // makeDenseView stores landmarks in id order after the vehicle pose.
        Eigen::VectorXd mean = view.stateMean();
        int k = 3;
        for (const long id : view.ids())
        {
            mean.segment<2>(k) = f(id, view.mean(id));
            k += 2;
        }
        view.setEstimate(mean, view.stateCov());
        partition.updateVertexPositions(view);
    }
};

TEST(HybridMetricMapLoopTest, RenderedMapFollowsCorrectedLandmarks)
{
    Fixture fx;
    const std::string before = fx.content();
    mrpt::maps::CSimplePointsMap pts0;
    fx.map.renderPoints(fx.partition, pts0);
    const auto p0 = pointsOf(pts0);

    // Loop-closure correction: a rotation by 10 deg, 2% scale and a shift of (3, -2).
    const double a = 10.0 * M_PI / 180.0, s = 1.02;
    Eigen::Matrix2d r;
    r << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    const auto t = [&](const V2& p) -> V2 { return s * r * p + V2(3, -2); };
    fx.moveLandmarks([&](long, const V2& p) { return t(p); });

    EXPECT_EQ(fx.content(), before) << "stored local content must not change";
    mrpt::maps::CSimplePointsMap pts1;
    fx.map.renderPoints(fx.partition, pts1);
    const auto p1 = pointsOf(pts1);
    ASSERT_EQ(p1.size(), p0.size());
    for (size_t i = 0; i < p0.size(); ++i) EXPECT_LT((p1[i] - t(p0[i])).norm(), 1e-4) << i;

    // Occupied cells lie along the corrected wall and cover it.
    mrpt::maps::COccupancyGridMap2D og;
    fx.map.renderOccupancy(fx.partition, 0.1, og);
    const auto occ = occupiedCellCentres(og, 0.8);
    const V2 w0 = t(V2(17, 0.3)), w1 = t(V2(17, 14.7));
    OutlineMetricsOptions mo;
    mo.closed = false;
    const auto m = evaluateOutlines(occ, {{w0, w1}}, mo);
    EXPECT_LT(m.p95_distance_m, 0.13);
    EXPECT_GT(m.coverage, 0.99);
    // ... and not along the old one.
    const auto old = evaluateOutlines(occ, {{V2(17, 0.3), V2(17, 14.7)}}, mo);
    EXPECT_GT(old.mean_distance_m, 1.0);
}

TEST(HybridMetricMapLoopTest, MovingOneLandmarkMovesOnlyItsRegionsBarycentrically)
{
    Fixture fx;
    const long moved = fx.lattice.id(3, 2);  // landmark at (15, 10)
    const V2 delta(0.4, -0.3);
    fx.moveLandmarks([&](long id, const V2& p) -> V2 { return id == moved ? V2(p + delta) : p; });
    size_t checked_moving = 0;
    for (const long id : fx.map.regionIds())
    {
        const auto& region = fx.partition.region(id);
        const auto* layer = fx.map.localMap(id)->layerAs<PointsLayer>(PointsLayer::kKind);
        mrpt::maps::CSimplePointsMap out;
        layer->renderInto(fx.partition.referenceToCurrent(id), out);
        const auto local = pointsOf(layer->points());
        const auto global = pointsOf(out);
        const hymm::ltr::TriangleFrame ref(region.reference);
        for (size_t i = 0; i < local.size(); ++i)
        {
            const Eigen::Vector3d wts = hymm::ltr::TriangleFrame::weights(ref.toLocal(local[i]));
            V2 expected = V2::Zero();
            for (int k = 0; k < 3; ++k) expected += wts[k] * region.current[static_cast<size_t>(k)];
            EXPECT_LT((global[i] - expected).norm(), 1e-4);
            const bool uses = std::count(region.vertex_ids.begin(), region.vertex_ids.end(), moved) > 0;
            if (!uses)
            {
                EXPECT_LT((global[i] - local[i]).norm(), 1e-4);
            }
            if (uses && (global[i] - local[i]).norm() > 1e-3) ++checked_moving;
        }
    }
    EXPECT_GT(checked_moving, 0u);
}

}  // namespace
