// Virtual landmarks (thesis Sec. 3.5.1): the apex geometry and its Jacobians, and where
// proposals are made for returns beyond a free edge of the partition.
#include "hymm/ltr/RegionPartition.h"
#include "hymm/ltr/TriangleFrame.h"
#include "hymm/ltr/VirtualLandmarks.h"
#include "synthetic_map.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

namespace
{
using namespace hymm::ltr;
using V2 = Eigen::Vector2d;

TEST(VirtualApex, JacobiansMatchNumericDifferentiation)
{
    const V2 a(1.0, -2.0), b(7.5, 3.0);
    for (const double side : {1.0, -1.0})
        for (const double depth : {2.0, 13.0})
        {
            Eigen::Matrix2d Ja, Jb;
            const V2 v = virtualApex(a, b, side, depth, &Ja, &Jb);
            // On the perpendicular bisector, at `depth`, on `side`.
            EXPECT_NEAR((v - 0.5 * (a + b)).dot(b - a), 0.0, 1e-9);
            EXPECT_NEAR((v - 0.5 * (a + b)).norm(), depth, 1e-9);
            const V2 e = b - a;
            EXPECT_GT(side * (e.x() * (v - a).y() - e.y() * (v - a).x()), 0);
            const double h = 1e-6;
            for (int k = 0; k < 2; ++k)
            {
                V2 d = V2::Zero();
                d[k] = h;
                const V2 na = (virtualApex(a + d, b, side, depth) - virtualApex(a - d, b, side, depth)) / (2 * h);
                const V2 nb = (virtualApex(a, b + d, side, depth) - virtualApex(a, b - d, side, depth)) / (2 * h);
                EXPECT_LT((Ja.col(k) - na).norm(), 1e-6);
                EXPECT_LT((Jb.col(k) - nb).norm(), 1e-6);
            }
        }
    EXPECT_THROW(virtualApex(a, a, 1.0, 3.0), std::invalid_argument);
}

struct OneRegion
{
    std::vector<V2> landmarks{V2(0, 0), V2(10, 0), V2(5, 8)};
    DenseCovarianceView view;
    RegionPartition partition;

    explicit OneRegion(const synthetic::SyntheticNoise& noise = {})
        : view(synthetic::makeSyntheticView(landmarks, Eigen::Vector3d(5, 3, 0), noise)),
          partition(permissive())
    {
        EXPECT_TRUE(partition.tryAddRegion({100, 101, 102}, view, 0.0).accepted());
    }
    static RegionPartition::Options permissive()
    {
        RegionPartition::Options o;
        o.conditions.min_vertex_correlation = 0;
        o.conditions.min_vehicle_correlation = 0;
        return o;
    }
};

// A wall 3 m below the edge (0,0)-(10,0), seen from inside the region.
std::vector<V2> wallBelow(int n)
{
    std::vector<V2> w;
    for (int i = 0; i < n; ++i) w.emplace_back(2.0 + 6.0 * i / std::max(1, n - 1), -3.0);
    return w;
}

TEST(VirtualLandmarks, ProposesAnApexThatHoldsTheReturnsBeyondAFreeEdge)
{
    OneRegion m;
    VirtualLandmarkOptions o;
    o.enabled = true;
    o.min_vehicle_correlation = 0.5;
    const auto wall = wallBelow(30);
    const auto props = proposeVirtualLandmarks(m.partition, m.view, wall, o);
    ASSERT_EQ(props.size(), 1u);
    const auto& p = props[0];
    EXPECT_EQ(std::min(p.a, p.b), 100);
    EXPECT_EQ(std::max(p.a, p.b), 101);
    EXPECT_EQ(p.points, wall.size());
    EXPECT_LT(p.position.y(), -3.0);  // beyond the wall, away from the region
    EXPECT_NEAR(p.position.x(), 5.0, 1e-9);
    EXPECT_TRUE(p.position.isApprox(
        virtualApex(m.view.mean(p.a), m.view.mean(p.b), p.side, p.depth), 1e-12));
    // Every return lies inside the proposed triangle.
    const TriangleFrame f(TriangleFrame::Vertices{m.view.mean(p.a), m.view.mean(p.b), p.position});
    for (const auto& w : wall) EXPECT_TRUE(f.contains(w)) << w.transpose();
}

TEST(VirtualLandmarks, NoProposalWithoutEnoughReturnsOrVehicleCorrelation)
{
    VirtualLandmarkOptions o;
    o.enabled = true;
    o.min_vehicle_correlation = 0.5;
    o.min_points = 10;
    {
        OneRegion m;
        EXPECT_TRUE(proposeVirtualLandmarks(m.partition, m.view, wallBelow(9), o).empty());
        // Returns on the region's side or beyond max_depth_m do not count.
        std::vector<V2> inside, deep;
        for (int i = 0; i < 20; ++i)
        {
            inside.emplace_back(4 + 0.1 * i, 2.0);
            deep.emplace_back(4 + 0.1 * i, -25.0);
        }
        EXPECT_TRUE(proposeVirtualLandmarks(m.partition, m.view, inside, o).empty());
        EXPECT_TRUE(proposeVirtualLandmarks(m.partition, m.view, deep, o).empty());
        o.enabled = false;
        EXPECT_TRUE(proposeVirtualLandmarks(m.partition, m.view, wallBelow(30), o).empty());
        o.enabled = true;
    }
    {
        // Vehicle nearly uncorrelated with the landmarks: no virtual vertex.
        synthetic::SyntheticNoise noise;
        noise.sigma_common = 0.01;
        noise.sigma_vehicle = 2.0;
        OneRegion m(noise);
        EXPECT_TRUE(proposeVirtualLandmarks(m.partition, m.view, wallBelow(30), o).empty());
    }
}

TEST(VirtualLandmarks, ApexThatWouldHoldALandmarkIsDropped)
{
    OneRegion m;
    m.landmarks.push_back(V2(5, -4));  // a landmark beyond the edge, inside the apex triangle
    DenseCovarianceView view = synthetic::makeSyntheticView(m.landmarks, Eigen::Vector3d(5, 3, 0));
    VirtualLandmarkOptions o;
    o.enabled = true;
    o.min_vehicle_correlation = 0.5;
    const auto props = proposeVirtualLandmarks(m.partition, view, wallBelow(30), o);
    for (const auto& p : props) EXPECT_FALSE(std::min(p.a, p.b) == 100 && std::max(p.a, p.b) == 101);
}

TEST(VirtualLandmarks, IniKeysAreChecked)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("VirtualLandmarks", "enabled", "true");
    cfg.write("VirtualLandmarks", "max_depth_m", "12");
    VirtualLandmarkOptions o;
    o.loadFromConfigFile(cfg, "VirtualLandmarks");
    EXPECT_TRUE(o.enabled);
    EXPECT_EQ(o.max_depth_m, 12.0);
    cfg.write("VirtualLandmarks", "max_dept_m", "12");
    EXPECT_THROW(o.loadFromConfigFile(cfg, "VirtualLandmarks"), std::invalid_argument);
    mrpt::config::CConfigFileMemory bad;
    bad.write("VirtualLandmarks", "min_depth_m", "30");
    EXPECT_THROW(o.loadFromConfigFile(bad, "VirtualLandmarks"), std::invalid_argument);
}

}  // namespace
