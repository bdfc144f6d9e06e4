// DenseSlam with [LtrPartition] local_refresh on the bundled chapter-3 rawlog: the
// per-step O(area) path (RegionPartition::updateNear) builds the same partition and
// dense map as the full refresh, and the regions near the vehicle follow the filter.
#include <gtest/gtest.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/io/RawlogReader.h>
#include <mrpt/config/CConfigFile.h>

#include <string>

namespace
{
using hymm::denseslam::DenseSlam;

const std::string kConfig = std::string(HYMM_SOURCE_DIR) + "/configs/ch3_slam.ini";
const std::string kRawlog = std::string(HYMM_SOURCE_DIR) + "/rawlogs/ch3_objects.rawlog";

DenseSlam makeSlam(bool local_refresh)
{
    mrpt::config::CConfigFile cfg(kConfig);
    DenseSlam::Options o;
    o.loadFromConfigFile(cfg, "DenseSlam");
    o.dense_layers = {"points", "occupancy"};
    hymm::ekf::EkfSlam::Options e;
    e.loadFromConfigFile(cfg, "EkfSlam");
    DenseSlam::DenseOptions d;
    d.loadFromConfigFile(cfg);
    d.partition.local_refresh = local_refresh;
    return DenseSlam(o, e, d, &cfg);
}

void runRawlog(DenseSlam& slam)
{
    hymm::io::RawlogReader reader(kRawlog);
    hymm::io::RawlogEntry entry;
    while (reader.next(entry)) slam.processEntry(entry);
}

TEST(DenseSlamLocalRefresh, SamePartitionAndDenseMapAsTheFullRefresh)
{
    DenseSlam full = makeSlam(false);
    DenseSlam local = makeSlam(true);
    runRawlog(full);
    runRawlog(local);
    ASSERT_GT(full.partition()->size(), 10u);
    ASSERT_GT(full.stats().returns_stored, 0u);

    // The filter never sees the dense part (UIF).
    EXPECT_TRUE(full.ekf().mean() == local.ekf().mean());
    // Same regions, same scans fused, same returns stored in the same regions.
    EXPECT_EQ(full.stats().regions_created, local.stats().regions_created);
    EXPECT_EQ(full.stats().regions_removed, local.stats().regions_removed);
    EXPECT_EQ(full.stats().returns_stored, local.stats().returns_stored);
    EXPECT_EQ(full.stats().returns_outside, local.stats().returns_outside);
    ASSERT_EQ(full.partition()->regionIds(), local.partition()->regionIds());
    const auto& lp = *local.partition();
    for (long id : full.partition()->regionIds())
    {
        EXPECT_EQ(full.partition()->region(id).vertex_ids, lp.region(id).vertex_ids);
        for (int k = 0; k < 3; ++k)
            EXPECT_EQ(full.partition()->region(id).reference[k], lp.region(id).reference[k]);
    }
    EXPECT_EQ(full.hybridMap()->regionIds(), local.hybridMap()->regionIds());
    for (long id : full.hybridMap()->regionIds())
        EXPECT_EQ(full.hybridMap()->localMap(id)->memoryBytes(),
                  local.hybridMap()->localMap(id)->memoryBytes())
            << "region " << id;

    // Regions the last scan could reach were refreshed to the filter's estimates.
    const double reach = local.hybridMap()->options().max_range_m;
    const Eigen::Vector2d v = local.ekf().vehiclePose().head<2>();
    size_t near = 0;
    for (long id : lp.regionsInBox(v - Eigen::Vector2d(reach, reach), v + Eigen::Vector2d(reach, reach)))
    {
        const auto& r = lp.region(id);
        for (int k = 0; k < 3; ++k)
        {
            if (!local.ekf().hasLandmark(r.vertex_ids[k])) continue;  // a virtual vertex
            EXPECT_LT((r.current[k] - local.ekf().landmarkMean(r.vertex_ids[k])).norm(), 1e-9)
                << "region " << id;
        }
        ++near;
    }
    EXPECT_GT(near, 0u);
}

}  // namespace
