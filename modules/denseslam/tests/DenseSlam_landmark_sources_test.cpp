// DenseSlam's scan-based landmark sources on synthetic scans with known objects: the
// reflector extractor (beacons), the tree extractor (trunks) and both on the same scan
// (laser_reflectors_and_trees), where an object seen by both extractors is one
// observation (the reflector's) and every feature keeps its own extractor's noise.
#include <gtest/gtest.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/extract/ReflectorExtractor.h>
#include <hymm/extract/TreeExtractor.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "../../extract/tests/synthetic_scan.h"

namespace
{
using hymm::denseslam::DenseSlam;
using namespace hymm::extract::testing;

constexpr int kBright = 8192;  // the car park's reflective tape (multiples of 8192)
constexpr int kDull = 0;
const Eigen::Vector3d kSensor(0.0, 0.0, 0.0);  // the vehicle at the origin, laser on it

// Sensor noise of each extractor, deliberately different so that a landmark's initial
// covariance tells which extractor's noise it got.
constexpr double kReflectorStdRange = 0.02, kReflectorStdBearing = 0.25 * kDeg;
constexpr double kTreeStdRange = 0.2, kTreeStdBearing = 2.0 * kDeg;

const Disc kPole{worldFromSensor(kSensor, 8.0, 25 * kDeg), 0.05, kBright};
const Disc kTrunk{worldFromSensor(kSensor, 10.0, -20 * kDeg), 0.3, kDull};
const Disc kReflectiveTrunk{worldFromSensor(kSensor, 7.0, 5 * kDeg), 0.2, kBright};

// A dull wall 20 m ahead behind the objects (beams past its ends get no return).
World withWall(std::vector<Disc> discs)
{
    World w;
    w.discs = std::move(discs);
    w.walls.push_back({worldFromSensor(kSensor, 20.0 / std::cos(70 * kDeg), -70 * kDeg),
                       worldFromSensor(kSensor, 20.0 / std::cos(70 * kDeg), 70 * kDeg), kDull});
    return w;
}

mrpt::obs::CObservation2DRangeScan::Ptr scanOf(const World& w)
{
    Laser l;  // 361 beams over 180 deg, as the car park's SICK
    l.intensity = true;
    return std::make_shared<mrpt::obs::CObservation2DRangeScan>(castScan(w, kSensor, l));
}

const std::vector<std::string> kReflectorsAndTrees{"laser_reflectors", "laser_trees"};

DenseSlam makeSlam(const std::vector<std::string>& sources, double same_object_distance = 1.0)
{
    DenseSlam::Options o;
    o.point_sources = sources;
    o.use_landmark_ids = false;
    o.same_object_distance = same_object_distance;
    hymm::extract::TreeExtractor::Options t;
    t.std_range = kTreeStdRange;
    t.std_bearing = kTreeStdBearing;
    hymm::extract::ReflectorExtractor::Options r;
    r.min_intensity = 1;
    r.std_range = kReflectorStdRange;
    r.std_bearing = kReflectorStdBearing;
    // The sources read their sections of the config, as hymm-slam's do.
    mrpt::config::CConfigFileMemory cfg;
    t.saveToConfigFile(cfg, "TreeExtractor");
    r.saveToConfigFile(cfg, "ReflectorExtractor");
    return DenseSlam(o, hymm::ekf::EkfSlam::Options{}, {}, &cfg);
}

void process(DenseSlam& slam, const mrpt::obs::CObservation2DRangeScan::Ptr& scan, int frames = 1)
{
    for (int i = 0; i < frames; ++i)
    {
        scan->timestamp = mrpt::Clock::fromDouble(1.0 + i);  // one scan a second
        mrpt::obs::CSensoryFrame sf;
        sf.insert(scan);
        slam.processFrame(sf);
    }
}

size_t count(const std::map<std::string, size_t>& m, const std::string& key)
{
    const auto it = m.find(key);
    return it == m.end() ? 0 : it->second;
}

/** The landmark nearest to `p` and its distance. */
std::pair<long, double> nearestLandmark(const DenseSlam& slam, const Eigen::Vector2d& p)
{
    std::pair<long, double> best{-1, std::numeric_limits<double>::infinity()};
    for (long id : slam.ekf().landmarkIds())
    {
        const double d = (slam.ekf().landmarkMean(id) - p).norm();
        if (d < best.second) best = {id, d};
    }
    return best;
}

/** With the vehicle known exactly (zero initial covariance), a landmark created from one
 *  observation has covariance G R G^T (Eq. 2.53), with eigenvalues std_range^2 and
 *  (range * std_bearing)^2 for G the Jacobian of the inverse observation model. */
void expectCreatedWithNoise(const DenseSlam& slam, long id, double std_range, double std_bearing)
{
    const double range = slam.ekf().landmarkMean(id).norm();
    const Eigen::Vector2d ev =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(slam.ekf().landmarkCov(id)).eigenvalues();
    const double a = std_range * std_range, b = range * range * std_bearing * std_bearing;
    EXPECT_NEAR(ev(0), std::min(a, b), 1e-3 * std::min(a, b)) << "landmark " << id;
    EXPECT_NEAR(ev(1), std::max(a, b), 1e-3 * std::max(a, b)) << "landmark " << id;
}

TEST(DenseSlamLandmarkSources, ReflectivePoleIsOneObservationWithTheReflectorNoise)
{
    auto slam = makeSlam(kReflectorsAndTrees);
    process(slam, scanOf(withWall({kPole})));
    const auto& s = slam.stats();
    EXPECT_EQ(count(s.point_features, "laser_reflectors"), 1u);
    EXPECT_EQ(count(s.point_features, "laser_trees"), 0u);  // 1-2 beams: too few for a trunk
    EXPECT_EQ(count(s.point_duplicates, "laser_trees"), 0u);
    EXPECT_EQ(s.extracted, 1u);
    EXPECT_EQ(s.observations, 1u);
    ASSERT_EQ(slam.ekf().numLandmarks(), 1u);
    const auto [id, error] = nearestLandmark(slam, kPole.centre);
    EXPECT_LT(error, 0.08);  // on the pole's visible surface (beacon_radius = 0)
    expectCreatedWithNoise(slam, id, kReflectorStdRange, kReflectorStdBearing);
    ASSERT_EQ(slam.landmarkFeatures().count(id), 1u);
    EXPECT_EQ(slam.landmarkFeatures().at(id).created_by, "laser_reflectors");
}

TEST(DenseSlamLandmarkSources, DullTrunkIsOneObservationWithTheTreeNoise)
{
    auto slam = makeSlam(kReflectorsAndTrees);
    process(slam, scanOf(withWall({kTrunk})));
    const auto& s = slam.stats();
    EXPECT_EQ(count(s.point_features, "laser_reflectors"), 0u);
    EXPECT_EQ(count(s.point_features, "laser_trees"), 1u);  // the wall is no trunk
    EXPECT_EQ(count(s.point_duplicates, "laser_trees"), 0u);
    EXPECT_EQ(s.observations, 1u);
    ASSERT_EQ(slam.ekf().numLandmarks(), 1u);
    const auto [id, error] = nearestLandmark(slam, kTrunk.centre);
    EXPECT_LT(error, 0.05);
    expectCreatedWithNoise(slam, id, kTreeStdRange, kTreeStdBearing);
    EXPECT_EQ(slam.landmarkFeatures().at(id).created_by, "laser_trees");
}

TEST(DenseSlamLandmarkSources, PoleAndTrunkTogetherAreTwoLandmarksEachWithItsNoise)
{
    const auto scan = scanOf(withWall({kPole, kTrunk}));
    auto slam = makeSlam(kReflectorsAndTrees);
    process(slam, scan, 4);  // the same scan again: re-observed, not re-created
    const auto& s = slam.stats();
    EXPECT_EQ(count(s.point_features, "laser_reflectors"), 4u);
    EXPECT_EQ(count(s.point_features, "laser_trees"), 4u);
    EXPECT_EQ(count(s.point_duplicates, "laser_trees"), 0u);
    EXPECT_EQ(s.observations, 8u);
    EXPECT_EQ(s.created, 2u);
    EXPECT_EQ(s.associated, 6u);
    ASSERT_EQ(slam.ekf().numLandmarks(), 2u);
    const auto pole = nearestLandmark(slam, kPole.centre);
    const auto trunk = nearestLandmark(slam, kTrunk.centre);
    EXPECT_LT(pole.second, 0.08);
    EXPECT_LT(trunk.second, 0.05);
    ASSERT_NE(pole.first, trunk.first);
    const auto& f = slam.landmarkFeatures();
    EXPECT_EQ(f.at(pole.first).created_by, "laser_reflectors");
    EXPECT_EQ(f.at(pole.first).count("laser_reflectors"), 4u);
    EXPECT_EQ(f.at(pole.first).count("laser_trees"), 0u);
    EXPECT_EQ(f.at(trunk.first).created_by, "laser_trees");
    EXPECT_EQ(f.at(trunk.first).count("laser_trees"), 4u);
    EXPECT_EQ(f.at(trunk.first).count("laser_reflectors"), 0u);
    EXPECT_DOUBLE_EQ(f.at(trunk.first).first_t, 1.0);
    EXPECT_DOUBLE_EQ(f.at(trunk.first).last_t, 4.0);

    // The initial covariances: one frame only.
    auto once = makeSlam(kReflectorsAndTrees);
    process(once, scan);
    expectCreatedWithNoise(once, nearestLandmark(once, kPole.centre).first, kReflectorStdRange,
                           kReflectorStdBearing);
    expectCreatedWithNoise(once, nearestLandmark(once, kTrunk.centre).first, kTreeStdRange,
                           kTreeStdBearing);

    // The single sources still see one object each.
    auto reflectors = makeSlam({"laser_reflectors"});
    process(reflectors, scan);
    EXPECT_EQ(reflectors.stats().observations, 1u);
    EXPECT_EQ(count(reflectors.stats().point_features, "laser_trees"), 0u);
    EXPECT_LT(nearestLandmark(reflectors, kPole.centre).second, 0.08);
    auto trees = makeSlam({"laser_trees"});
    process(trees, scan);
    EXPECT_EQ(trees.stats().observations, 1u);
    EXPECT_EQ(count(trees.stats().point_features, "laser_reflectors"), 0u);
    EXPECT_LT(nearestLandmark(trees, kTrunk.centre).second, 0.05);
}

TEST(DenseSlamLandmarkSources, ReflectiveTrunkIsObservedOnceAsTheReflector)
{
    // Tape all around the trunk, and tape on the middle beams only: both extractors find
    // the trunk, the tree is dropped (its beams overlap the reflector's).
    const auto full = scanOf(withWall({kReflectiveTrunk, kTrunk}));
    auto tape = scanOf(withWall({kReflectiveTrunk, kTrunk}));
    std::vector<size_t> bright;
    for (size_t i = 0; i < tape->getScanSize(); ++i)
        if (tape->getScanIntensity(i) > 0) bright.push_back(i);
    ASSERT_GE(bright.size(), 5u);
    tape->setScanIntensity(bright.front(), kDull);
    tape->setScanIntensity(bright.back(), kDull);

    for (const auto& scan : {full, tape})
    {
        auto slam = makeSlam(kReflectorsAndTrees, 0.0);
        process(slam, scan, 3);
        const auto& s = slam.stats();
        EXPECT_EQ(count(s.point_features, "laser_reflectors"), 3u);
        EXPECT_EQ(count(s.point_features, "laser_trees"), 6u);  // the reflective trunk and the dull one
        EXPECT_EQ(count(s.point_duplicates, "laser_trees"), 3u);
        EXPECT_EQ(s.observations, 6u);
        ASSERT_EQ(slam.ekf().numLandmarks(), 2u);
        const auto lm = nearestLandmark(slam, kReflectiveTrunk.centre);
        EXPECT_LT(lm.second, kReflectiveTrunk.radius + 0.05);  // on the taped surface
        const auto& f = slam.landmarkFeatures().at(lm.first);
        EXPECT_EQ(f.created_by, "laser_reflectors");
        EXPECT_EQ(f.count("laser_reflectors"), 3u);
        EXPECT_EQ(f.count("laser_trees"), 0u);
        EXPECT_EQ(slam.landmarkFeatures().at(nearestLandmark(slam, kTrunk.centre).first).created_by,
                  "laser_trees");
    }

    // Without the rule (the trees-only source) the trunk is a tree landmark at its centre.
    auto trees = makeSlam({"laser_trees"});
    process(trees, full);
    EXPECT_EQ(trees.stats().observations, 2u);
    EXPECT_LT(nearestLandmark(trees, kReflectiveTrunk.centre).second, 0.05);
}

TEST(DenseSlamLandmarkSources, TreeNextToAReflectorIsDroppedWithinTheSameObjectDistance)
{
    // A beacon pole 0.4 m behind the trunk and 0.6 m to its side: separate beams (the
    // trunk spans +-1.7 deg, the pole sits 3.4 deg off), 0.72 m between the centres.
    const Eigen::Vector2d along = kTrunk.centre.normalized();
    const Eigen::Vector2d side(-along.y(), along.x());
    const Disc pole{kTrunk.centre + 0.4 * along + 0.6 * side, 0.05, kBright};
    const auto scan = scanOf(withWall({kTrunk, pole}));

    auto near = makeSlam(kReflectorsAndTrees, 1.0);
    process(near, scan);
    EXPECT_EQ(count(near.stats().point_features, "laser_reflectors"), 1u);
    EXPECT_EQ(count(near.stats().point_features, "laser_trees"), 1u);
    EXPECT_EQ(count(near.stats().point_duplicates, "laser_trees"), 1u);
    EXPECT_EQ(near.stats().observations, 1u);
    EXPECT_LT(nearestLandmark(near, pole.centre).second, 0.08);

    auto apart = makeSlam(kReflectorsAndTrees, 0.5);
    process(apart, scan);
    EXPECT_EQ(count(apart.stats().point_duplicates, "laser_trees"), 0u);
    EXPECT_EQ(apart.stats().observations, 2u);
    EXPECT_LT(nearestLandmark(apart, kTrunk.centre).second, 0.05);
}

TEST(DenseSlamLandmarkSources, ConfigNamesAndErrors)
{
    auto load = [](const std::string& body)
    {
        mrpt::config::CConfigFileMemory cfg("[DenseSlam]\n" + body);
        DenseSlam::Options o;
        o.loadFromConfigFile(cfg, "DenseSlam");
        return o;
    };
    const auto o =
        load("landmark_source = laser_reflectors_and_trees\nsame_object_distance_m = 0.7\n");
    EXPECT_EQ(o.point_sources, kReflectorsAndTrees);
    EXPECT_DOUBLE_EQ(o.same_object_distance, 0.7);
    EXPECT_EQ(load("landmark_source = laser_reflectors\n").point_sources,
              std::vector<std::string>{"laser_reflectors"});
    EXPECT_EQ(load("landmark_source = laser_trees\n").point_sources, std::vector<std::string>{"laser_trees"});
    // The aliases are their sources; the sources are kept in registry order.
    EXPECT_EQ(load("landmark_source = laser_trees, laser_reflectors\n").point_sources, kReflectorsAndTrees);
    EXPECT_EQ(load("landmark_source = both\n").point_sources,
              (std::vector<std::string>{"bearing_range", "laser_trees"}));
    EXPECT_EQ(load("landmark_source = laser_trees,bearing_range\n").point_sources,
              (std::vector<std::string>{"bearing_range", "laser_trees"}));
    EXPECT_THROW(load("landmark_source = both, laser_trees\n"), std::invalid_argument);
    EXPECT_THROW(load("landmark_source = reflectors_and_trees\n"), std::invalid_argument);
    EXPECT_THROW(load("same_object_distance_m = -1\n"), std::invalid_argument);

    // Round trip through saveToConfigFile.
    mrpt::config::CConfigFileMemory out;
    o.saveToConfigFile(out, "DenseSlam");
    DenseSlam::Options back;
    back.loadFromConfigFile(out, "DenseSlam");
    EXPECT_EQ(back.point_sources, kReflectorsAndTrees);
    EXPECT_DOUBLE_EQ(back.same_object_distance, 0.7);
    // Written back as the alias the configs use.
    EXPECT_EQ(out.read_string("DenseSlam", "landmark_source", ""), "laser_reflectors_and_trees");
}

// Every registered point source builds with its name and input, and the pipeline builds
// exactly the ones landmark_source names, in registry order.
TEST(DenseSlamLandmarkSources, RegisteredPointSourcesBuild)
{
    for (const auto& kind : hymm::denseslam::pointSourceKinds())
    {
        const auto src = kind.make(nullptr, {});
        EXPECT_EQ(src->name(), kind.name);
        EXPECT_EQ(src->input(), kind.input);
        EXPECT_EQ(hymm::denseslam::findPointSourceKind(kind.name), &kind);
    }
    EXPECT_EQ(hymm::denseslam::findPointSourceKind("scan_landmarks"), nullptr);
    auto slam = makeSlam({"laser_trees", "laser_reflectors"});
    ASSERT_EQ(slam.pointSources().size(), 2u);
    EXPECT_EQ(slam.pointSources()[0]->name(), "laser_reflectors");
    EXPECT_EQ(slam.pointSources()[1]->name(), "laser_trees");
    EXPECT_TRUE(slam.options().readsPoints(hymm::denseslam::PointSourceInput::Scan));
    EXPECT_FALSE(slam.options().readsPoints(hymm::denseslam::PointSourceInput::BearingRange));
    DenseSlam::Options unknown;
    unknown.point_sources = {"laser_poles"};
    EXPECT_THROW(DenseSlam(unknown, hymm::ekf::EkfSlam::Options{}), std::invalid_argument);
}

// landmark_source lists point sources and any registered per-scan sources; the pipeline
// builds the registered ones with their sections.
TEST(DenseSlamLandmarkSources, RegisteredScanSourcesParseAndBuild)
{
    auto load = [](const std::string& body) {
        mrpt::config::CConfigFileMemory cfg("[DenseSlam]\n" + body);
        DenseSlam::Options o;
        o.loadFromConfigFile(cfg, "DenseSlam");
        return o;
    };
    const auto alone = load("landmark_source = scan_landmarks\n");
    EXPECT_TRUE(alone.point_sources.empty());
    EXPECT_EQ(alone.scan_sources, std::vector<std::string>{"scan_landmarks"});
    const auto both = load("landmark_source = laser_reflectors, scan_landmarks\n");
    EXPECT_EQ(both.point_sources, std::vector<std::string>{"laser_reflectors"});
    EXPECT_EQ(both.scan_sources, std::vector<std::string>{"scan_landmarks"});
    EXPECT_TRUE(load("landmark_source = bearing_range\n").scan_sources.empty());
    EXPECT_THROW(load("landmark_source = scan_landmarks,scan_landmarks\n"), std::invalid_argument);
    EXPECT_THROW(load("landmark_source = scan_landmark\n"), std::invalid_argument);
    EXPECT_THROW(load("landmark_source =  ,\n"), std::invalid_argument);
    mrpt::config::CConfigFileMemory out;
    both.saveToConfigFile(out, "DenseSlam");
    DenseSlam::Options back;
    back.loadFromConfigFile(out, "DenseSlam");
    EXPECT_EQ(back.point_sources, std::vector<std::string>{"laser_reflectors"});
    EXPECT_EQ(back.scan_sources, both.scan_sources);

    // fromConfig builds the source with its sections; a bad key there is an error.
    mrpt::config::CConfigFileMemory cfg(
        "[DenseSlam]\nlandmark_source = scan_landmarks\n[ScanLandmarks]\nmatcher = icp\n");
    const auto slam = DenseSlam::fromConfig(cfg);
    ASSERT_NE(slam.scanLandmarks(), nullptr);
    EXPECT_EQ(slam.scanLandmarks()->map().matcher().name(), "icp");
    mrpt::config::CConfigFileMemory bad(
        "[DenseSlam]\nlandmark_source = scan_landmarks\n[ScanLandmarks]\nmatchr = icp\n");
    EXPECT_THROW(DenseSlam::fromConfig(bad), std::invalid_argument);
    // Without it, nothing is built and no counter appears.
    EXPECT_EQ(DenseSlam::fromConfig(mrpt::config::CConfigFileMemory("")).scanSources().size(), 0u);
}

}  // namespace
