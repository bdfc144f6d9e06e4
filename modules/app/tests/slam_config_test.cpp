// hymm-slam's strict configuration: every bundled config loads; malformed ones are
// errors naming the file, line, section, key and the value as written.
#include <gtest/gtest.h>
#include <hymm/app/slam_config.h>
#include <hymm/core/StrictConfigFile.h>
#include <hymm/sim/Scenario.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <filesystem>
#include <fstream>

namespace
{
namespace fs = std::filesystem;
using hymm::app::loadSlamConfig;
using hymm::core::ConfigError;
using hymm::core::StrictConfigFile;

std::vector<fs::path> inis(const fs::path& dir)
{
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".ini") out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

std::string errorOf(const std::string& text)
{
    try
    {
        loadSlamConfig(StrictConfigFile::fromText(text, "slam.ini"));
    }
    catch (const ConfigError& e)
    {
        return e.what();
    }
    return "";
}

void expectError(const std::string& text, const std::string& part)
{
    const std::string e = errorOf(text);
    EXPECT_NE(e.find("config file 'slam.ini'"), std::string::npos) << text << "\n-> " << e;
    EXPECT_NE(e.find(part), std::string::npos) << text << "\n-> " << e;
}

TEST(SlamConfigTest, EveryBundledConfigLoadsStrictly)
{
    const fs::path root = HYMM_SOURCE_DIR;
    size_t slam = 0, sim = 0, datasets = 0;
    for (const auto& p : inis(root / "configs"))
    {
        EXPECT_NO_THROW(loadSlamConfig(p.string())) << p;
        ++slam;
    }
    for (const auto& p : inis(root / "configs" / "sim"))
    {
        EXPECT_NO_THROW(hymm::sim::Scenario::fromFile(p.string())) << p;
        ++sim;
    }
    // Importer configs are read by hymm-import / hymm-calibrate (each reads some of the
    // sections): the file-level checks apply.
    for (const auto& p : inis(root / "configs" / "datasets"))
    {
        EXPECT_NO_THROW(StrictConfigFile f(p.string())) << p;
        ++datasets;
    }
    EXPECT_GE(slam, 10u);
    EXPECT_GE(sim, 5u);
    EXPECT_GE(datasets, 3u);
}

TEST(SlamConfigTest, MalformedFilesAreClearErrors)
{
    expectError("", "holds no [section]");
    expectError("; only a comment\n", "holds no [section]");
    expectError(std::string("\x89PNG\r\n\x1a\n\0\0", 10), "binary content");
    expectError("[EkfSlamm]\nassociation_method = jcbb\n", "line 1: unknown section [EkfSlamm]");
    expectError("[EkfSlam]\nassociation_method = nn\nassociation_method = jcbb\n",
                "line 3: duplicate key 'association_method'");
    expectError("[EkfSlam]\nprune_tentative = true\n[DenseSlam]\nmin_range = 1\n[EkfSlam]\njacobians = current\n",
                "line 5: duplicate section [EkfSlam]");
    expectError("[EkfSlam]\n", "section [EkfSlam] holds no key");
    expectError("[DenseSlam]\nmin_range = 0\n[EkfSlam]\nconfirm_min_observations = 5000000000\n",
                "line 4: [EkfSlam] confirm_min_observations=5000000000: out of range");
    expectError("[ClassicOccupancyGrid]\ny_max_m = 1e308\n",
                "line 2: [ClassicOccupancyGrid] y_max_m=1e308: out of range");
    expectError("[OccupancyLayer]\ncell_size_m = 1e-6\n", "[OccupancyLayer] cell_size_m=1e-6: out of range");
    expectError("[DenseSlam]\ndense_layers = points,voxels\n", "[DenseSlam] dense_layers=points,voxels");
    expectError("[TreeExtractor]\nstd_bearing_deg = 0.5deg\n", "std_bearing_deg=0.5deg: not a number");
    expectError("[HybridMetricMap]\nenable_sog = maybe\n", "line 2: [HybridMetricMap] enable_sog=maybe");
    expectError("[DelayedDenseStore]\nmax_stored_points = -3\n", "max_stored_points=-3: out of range");
    expectError("[LtrPartition]\nmin_angle_deg = 60\n", "min_angle_deg=60: out of range, must be [0, 60)");
    EXPECT_EQ(errorOf("[EkfSlam]\nassociation_method = jcbb\n"), "");
}

// [Laser] owns a laser return's noise; the keys it replaced still work (deprecated) unless
// [Laser] sets the same quantity.
TEST(SlamConfigTest, LaserSectionSetsTheNoiseOfEveryUser)
{
    const auto slam = loadSlamConfig(StrictConfigFile::fromText(
        "[DenseSlam]\ndense_layers = particles,sog\n[Laser]\nstd_range_m = 0.2\nstd_bearing_deg = 2\n", "l.ini"));
    EXPECT_EQ(slam.options().laser_std_range, 0.2);
    EXPECT_EQ(slam.options().laser_std_bearing, 2 * (M_PI / 180.0));
    const auto old = loadSlamConfig(StrictConfigFile::fromText("[DenseSlam]\nlaser_std_range = 0.3\n", "o.ini"));
    EXPECT_EQ(old.options().laser_std_range, 0.3);
    expectError("[DenseSlam]\nlaser_std_range = 0.3\n[Laser]\nstd_range_m = 0.2\n",
                "line 2: [DenseSlam] laser_std_range=0.3: the laser noise is set in [Laser] std_range_m");
    expectError("[SogLayer]\nbearing_std_deg = 1\n[Laser]\nstd_bearing_deg = 2\n",
                "[SogLayer] bearing_std_deg=1: the laser noise is set in [Laser] std_bearing_deg");
    expectError("[Laser]\nstd_range_m = 0\n", "line 2: [Laser] std_range_m=0: out of range, must be (0, 10]");
}

// The saver writes every declared key and the loader reads back the same values: a save
// of the defaults, loaded into fresh options, saves identically (also for scaled keys).
TEST(SlamConfigTest, EverySectionRoundTripsThroughSaveAndLoad)
{
    for (const auto& s : hymm::app::optionSections())
    {
        std::shared_ptr<void> a, b;
        mrpt::config::CConfigFileMemory first, second;
        s.table(a).save(first, s.section);
        const auto tb = s.table(b);
        tb.load(first, s.section);
        tb.save(second, s.section);
        std::string t1, t2;
        first.getContent(t1);
        second.getContent(t2);
        EXPECT_EQ(t1, t2) << s.section;
        EXPECT_FALSE(tb.keys().empty()) << s.section;
        for (const auto& k : tb.keys()) EXPECT_FALSE(k.doc.empty()) << s.section << " " << k.name;
    }
}

TEST(SlamConfigTest, TheReadmeTablesMatchTheDeclarations)
{
    const auto stale = hymm::app::syncReadmeTables(HYMM_SOURCE_DIR, false);
    for (const auto& s : stale) ADD_FAILURE() << "README table out of date: " << s;
}

}  // namespace
