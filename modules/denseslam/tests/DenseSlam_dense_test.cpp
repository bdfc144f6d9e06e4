// DenseSlam with the dense layers on the bundled chapter-3 rawlog: unidirectional
// information flow (the feature map and the path do not depend on the dense layers,
// bit for bit), regions hang off the filter's landmarks, and the dense_layers key.
#include <gtest/gtest.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/denseslam/RawlogReader.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <string>

namespace
{
using hymm::denseslam::DenseSlam;

const std::string kConfig = std::string(HYMM_SOURCE_DIR) + "/configs/ch3_slam.ini";
const std::string kRawlog = std::string(HYMM_SOURCE_DIR) + "/rawlogs/ch3_objects.rawlog";

// configs/ch3_slam.ini (landmark detector as landmark source) with the dense part set.
DenseSlam makeSlam(bool points, bool occupancy, bool classic)
{
    mrpt::config::CConfigFile cfg(kConfig);
    DenseSlam::Options o;
    o.loadFromConfigFile(cfg, "DenseSlam");
    EXPECT_EQ(o.landmark_source, DenseSlam::LandmarkSource::BearingRange);
    o.dense_points = points;
    o.dense_occupancy = occupancy;
    o.classic_grid = classic;
    hymm::ekf::EkfSlam::Options e;
    e.loadFromConfigFile(cfg, "EkfSlam");
    hymm::extract::TreeExtractor::Options t;
    t.loadFromConfigFile(cfg, "TreeExtractor");
    hymm::extract::ReflectorExtractor::Options r;
    r.loadFromConfigFile(cfg, "ReflectorExtractor");
    DenseSlam::DenseOptions d;
    d.loadFromConfigFile(cfg);
    return DenseSlam(o, e, t, r, d);
}

void runRawlog(DenseSlam& slam)
{
    hymm::denseslam::RawlogReader reader(kRawlog);
    hymm::denseslam::RawlogEntry entry;
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
        return std::make_pair(o.dense_points, o.dense_occupancy);
    };
    EXPECT_EQ(parse("none"), std::make_pair(false, false));
    EXPECT_EQ(parse("points"), std::make_pair(true, false));
    EXPECT_EQ(parse("occupancy"), std::make_pair(false, true));
    EXPECT_EQ(parse("points, occupancy"), std::make_pair(true, true));
    EXPECT_EQ(parse("occupancy,points"), std::make_pair(true, true));
    EXPECT_ANY_THROW(parse("points,grid"));
    EXPECT_ANY_THROW(parse("points,points"));
    EXPECT_ANY_THROW(parse(""));

    mrpt::config::CConfigFileMemory none;
    DenseSlam::Options o;
    o.loadFromConfigFile(none, "DenseSlam");
    EXPECT_FALSE(o.denseLayers());
    EXPECT_FALSE(o.classic_grid);

    // Only the layers named in [DenseSlam] are built.
    DenseSlam::Options only_points;
    only_points.dense_points = true;
    const DenseSlam s(only_points, hymm::ekf::EkfSlam::Options(), hymm::extract::TreeExtractor::Options());
    ASSERT_NE(s.hybridMap(), nullptr);
    EXPECT_TRUE(s.hybridMap()->options().enable_points);
    EXPECT_FALSE(s.hybridMap()->options().enable_occupancy);
    EXPECT_EQ(s.classicGrid(), nullptr);
}

TEST(DenseSlamDense, UnknownKeyInADenseSectionIsAnError)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("LtrPartition", "no_such_key", 1);
    DenseSlam::DenseOptions d;
    EXPECT_ANY_THROW(d.loadFromConfigFile(cfg));
}

}  // namespace
