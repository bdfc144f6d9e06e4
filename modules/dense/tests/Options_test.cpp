/**
 * @file Options_test.cpp
 * @brief Strict ini loading of every options struct of the module.
 */
#include "hymm/dense/ClassicOccupancyGrid.h"
#include "hymm/dense/HybridMetricMap.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

namespace
{
using namespace hymm::dense;

TEST(DenseOptionsTest, LoadsAllSections)
{
    mrpt::config::CConfigFileMemory cfg(
        "[HybridMetricMap]\nenable_points=false\nmax_range_m=30\n"
        "[OccupancyLayer]\ncell_size_m=0.2\nprob_hit=0.8\nprob_clamp_max=0.99\n"
        "[PointsLayer]\nvoxel_size_m=0.05\n");
    HybridMetricMap::Options o;
    o.loadAll(cfg);
    EXPECT_FALSE(o.enable_points);
    EXPECT_TRUE(o.enable_occupancy);
    EXPECT_DOUBLE_EQ(o.max_range_m, 30);
    EXPECT_DOUBLE_EQ(o.occupancy.cell_size_m, 0.2);
    EXPECT_DOUBLE_EQ(o.occupancy.prob_hit, 0.8);
    EXPECT_DOUBLE_EQ(o.occupancy.prob_miss, 0.4);  // default kept
    EXPECT_DOUBLE_EQ(o.points.voxel_size_m, 0.05);

    mrpt::config::CConfigFileMemory saved;
    o.saveAll(saved);
    HybridMetricMap::Options back;
    back.loadAll(saved);
    EXPECT_EQ(back.enable_points, o.enable_points);
    EXPECT_DOUBLE_EQ(back.occupancy.prob_clamp_max, 0.99);
    EXPECT_DOUBLE_EQ(back.points.voxel_size_m, 0.05);
}

TEST(DenseOptionsTest, RejectsUnknownKeysAndBadValues)
{
    const auto load = [](const std::string& text) {
        mrpt::config::CConfigFileMemory cfg(text);
        HybridMetricMap::Options o;
        o.loadAll(cfg);
    };
    EXPECT_THROW(load("[HybridMetricMap]\nmax_rnge_m=3\n"), std::exception);
    EXPECT_THROW(load("[HybridMetricMap]\nmax_range_m=-1\n"), std::exception);
    EXPECT_THROW(load("[HybridMetricMap]\nmax_range_m=far\n"), std::exception);
    EXPECT_THROW(load("[HybridMetricMap]\nenable_points=maybe\n"), std::exception);
    EXPECT_THROW(load("[HybridMetricMap]\nenable_points=false\nenable_occupancy=false\n"), std::exception);
    EXPECT_THROW(load("[OccupancyLayer]\ncell_size_m=0\n"), std::exception);
    EXPECT_THROW(load("[OccupancyLayer]\nprob_hit=0.4\n"), std::exception);   // not above the prior
    EXPECT_THROW(load("[OccupancyLayer]\nprob_miss=0.6\n"), std::exception);  // not below the prior
    EXPECT_THROW(load("[OccupancyLayer]\nprob_clamp_max=1\n"), std::exception);
    EXPECT_THROW(load("[OccupancyLayer]\ncell_sz=0.1\n"), std::exception);
    EXPECT_THROW(load("[PointsLayer]\nvoxel_size_m=-0.1\n"), std::exception);

    ClassicOccupancyGrid::Options c;
    mrpt::config::CConfigFileMemory good("[ClassicOccupancyGrid]\nx_min_m=-10\nx_max_m=10\n");
    c.loadFromConfigFile(good, "ClassicOccupancyGrid");
    EXPECT_DOUBLE_EQ(c.x_min_m, -10);
    mrpt::config::CConfigFileMemory bad("[ClassicOccupancyGrid]\nx_min_m=10\nx_max_m=-10\n");
    EXPECT_THROW(c.loadFromConfigFile(bad, "ClassicOccupancyGrid"), std::exception);
    mrpt::config::CConfigFileMemory typo("[ClassicOccupancyGrid]\nxmin=1\n");
    EXPECT_THROW(c.loadFromConfigFile(typo, "ClassicOccupancyGrid"), std::exception);
}

}  // namespace
