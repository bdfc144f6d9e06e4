// Why a return lies in no region (ltr/outside_causes.h): each cause on a landmark grid
// built to produce it.
#include "hymm/ltr/RegionPartition.h"
#include "hymm/ltr/outside_causes.h"
#include "synthetic_map.h"

#include <gtest/gtest.h>

#include <string>

namespace
{
using namespace hymm::ltr;
using V2 = Eigen::Vector2d;

// 3 x 3 landmarks 10 m apart; id 100 + 3 row + column.
std::vector<V2> grid()
{
    std::vector<V2> out;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) out.emplace_back(10.0 * c, 10.0 * r);
    return out;
}

RegionPartition::Options options(double max_edge)
{
    RegionPartition::Options o;
    o.conditions.min_vertex_correlation = 0.5;
    o.conditions.min_vehicle_correlation = 0.0;
    o.conditions.max_edge_length_m = max_edge;
    return o;
}

TEST(OutsideCauses, EachCauseWhereItHolds)
{
    const auto view = synthetic::makeSyntheticView(grid(), Eigen::Vector3d(10, 10, 0));
    RegionPartition partition(options(50));
    ASSERT_TRUE(partition.tryAddRegion({100, 101, 103}, view, 0).accepted());
    EXPECT_EQ(classifyOutsideReturn(partition, view, V2(2, 2)), OutsideCause::InRegionNow);
    EXPECT_EQ(classifyOutsideReturn(partition, view, V2(30, 5)), OutsideCause::NoLandmarkTriangle);
    EXPECT_EQ(classifyOutsideReturn(partition, view, V2(-1, 25)), OutsideCause::NoLandmarkTriangle);
    // Inside the landmarks, in a triangle that passes every condition but was never grown.
    EXPECT_EQ(classifyOutsideReturn(partition, view, V2(15, 5)), OutsideCause::NotGrown);
    EXPECT_EQ(classifyOutsideReturn(partition, view, V2(12, 17)), OutsideCause::NotGrown);

    // The squares' halves have a 14.1 m edge: too long for 12 m.
    RegionPartition short_edges(options(12));
    EXPECT_EQ(classifyOutsideReturn(short_edges, view, V2(15, 5)), OutsideCause::LongEdge);

    // Independent landmarks (no common error): the vertex correlation condition fails.
    synthetic::SyntheticNoise independent;
    independent.sigma_common = 0.0;
    const auto loose = synthetic::makeSyntheticView(grid(), Eigen::Vector3d(10, 10, 0), independent);
    RegionPartition empty(options(50));
    EXPECT_EQ(classifyOutsideReturn(empty, loose, V2(15, 5)), OutsideCause::Correlation);

    OutsideCauseCounts n;
    ++n[OutsideCause::Shape];
    ++n[OutsideCause::Shape];
    ++n[OutsideCause::Overlap];
    EXPECT_EQ(n.total(), 3u);
    EXPECT_EQ(std::string(toString(OutsideCause::NoLandmarkTriangle)), "no_landmark_triangle");
}

}  // namespace
