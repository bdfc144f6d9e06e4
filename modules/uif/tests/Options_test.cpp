/**
 * @file Options_test.cpp
 * @brief [DelayedDenseStore] loads strictly and round-trips.
 */
#include <hymm/uif/DelayedDenseStore.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

namespace
{
using hymm::uif::DelayedDenseStore;

TEST(DelayedDenseStoreOptionsTest, DefaultsAreOffAndValid)
{
    DelayedDenseStore::Options o;
    EXPECT_FALSE(o.enabled);
    EXPECT_TRUE(o.require_potential_region);  // thesis Sec. 3.7.3
    EXPECT_NO_THROW(o.validate());
}

TEST(DelayedDenseStoreOptionsTest, LoadsEveryKeyAndRoundTrips)
{
    mrpt::config::CConfigFileMemory cfg(
        "[DelayedDenseStore]\nenabled = true\nrequire_potential_region = false\n"
        "max_stored_points = 123\nmax_stored_scans = 7\n"
        "max_age_s = 12.5\nsearch_radius_m = 30\nmax_candidate_landmarks = 6\n"
        "fuse_free_space = false\nfirst_passive_id = 5000\nenable_profiler = false\n");
    DelayedDenseStore::Options o;
    o.loadFromConfigFile(cfg, "DelayedDenseStore");
    EXPECT_TRUE(o.enabled);
    EXPECT_FALSE(o.require_potential_region);
    EXPECT_EQ(o.max_stored_points, 123u);
    EXPECT_EQ(o.max_stored_scans, 7u);
    EXPECT_DOUBLE_EQ(o.max_age_s, 12.5);
    EXPECT_DOUBLE_EQ(o.search_radius_m, 30.0);
    EXPECT_EQ(o.max_candidate_landmarks, 6);
    EXPECT_FALSE(o.fuse_free_space);
    EXPECT_EQ(o.first_passive_id, 5000);

    mrpt::config::CConfigFileMemory out;
    o.saveToConfigFile(out, "DelayedDenseStore");
    DelayedDenseStore::Options back;
    back.loadFromConfigFile(out, "DelayedDenseStore");
    EXPECT_EQ(back.enabled, o.enabled);
    EXPECT_EQ(back.require_potential_region, o.require_potential_region);
    EXPECT_EQ(back.max_stored_points, o.max_stored_points);
    EXPECT_EQ(back.max_stored_scans, o.max_stored_scans);
    EXPECT_DOUBLE_EQ(back.max_age_s, o.max_age_s);
    EXPECT_DOUBLE_EQ(back.search_radius_m, o.search_radius_m);
    EXPECT_EQ(back.max_candidate_landmarks, o.max_candidate_landmarks);
    EXPECT_EQ(back.fuse_free_space, o.fuse_free_space);
    EXPECT_EQ(back.first_passive_id, o.first_passive_id);
}

TEST(DelayedDenseStoreOptionsTest, UnknownKeysAndBadValuesAreErrors)
{
    DelayedDenseStore::Options o;
    mrpt::config::CConfigFileMemory typo("[DelayedDenseStore]\nmax_stored_point = 5\n");
    EXPECT_THROW(o.loadFromConfigFile(typo, "DelayedDenseStore"), std::invalid_argument);
    for (const char* bad :
         {"max_stored_points = 0", "max_stored_scans = -1", "max_age_s = -2", "search_radius_m = 0",
          "max_candidate_landmarks = 2", "enabled = maybe", "first_passive_id = -4",
          "require_potential_region = 2"})
    {
        mrpt::config::CConfigFileMemory cfg(std::string("[DelayedDenseStore]\n") + bad + "\n");
        DelayedDenseStore::Options p;
        EXPECT_THROW(p.loadFromConfigFile(cfg, "DelayedDenseStore"), std::invalid_argument) << bad;
    }
    o.max_candidate_landmarks = 1;
    EXPECT_THROW(DelayedDenseStore{o}, std::invalid_argument);
}

}  // namespace
