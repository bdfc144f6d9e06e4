// hymm-slam (SlamApp) on rawlogs/ch3_objects.rawlog with configs/ch3_slam.ini, its MRPT
// outputs read back through MRPT's own readers:
//  - map.3Dscene (COpenGLScene::loadFromFile): the named objects SceneViewer3D shows;
//  - map.simplemap (CSimpleMap::loadFromFile): a keyframe per path sample, with the
//    pose estimate, its covariance and the laser scan; an occupancy grid MRPT builds
//    from it agrees with the HYMM occupancy layer cell by cell;
//  - run.rawlog (CRawlog::loadFromRawLogFile): the input observations, each frame
//    after a CObservationRobotPose with the pose estimate of that step and a
//    CObservationOdometry with the input's odometry up to it;
//  - map.hymm, created through CMultiMetricMap from an .ini section: MRPT's
//    CMonteCarloLocalization2D localises simulated runs of the same world (other
//    seeds than the mapping run) on it, scored against the simulator's true path, and
//    better than on a grid MRPT builds from map.simplemap.
#include <Eigen/Dense>
#include "grid_agreement.h"

#include <gtest/gtest.h>
#include <hymm/app/SlamApp.h>
#include <hymm/app/mrpt_outputs.h>
#include <hymm/dense/CHybridMetricMap.h>
#include <hymm/sim/Simulator.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/slam/CMonteCarloLocalization2D.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace
{
namespace fs = std::filesystem;
using hymm::app::SlamApp;

const std::string kSrc = HYMM_SOURCE_DIR;

// One hymm-slam run shared by the tests (the run is the expensive part).
struct Run
{
    std::string out;
    std::unique_ptr<SlamApp> app;
};

const Run& run()
{
    static const Run r = [] {
        Run x;
        x.out = (fs::temp_directory_path() / ("hymm_mrpt_workflow_" + std::to_string(getpid()))).string();
        SlamApp::Args a;
        a.config = kSrc + "/configs/ch3_slam.ini";
        a.rawlog = kSrc + "/rawlogs/ch3_objects.rawlog";
        a.out_dir = x.out;
        a.quiet = true;
        a.png = false;
        x.app = std::make_unique<SlamApp>(a);
        std::ostringstream log;
        x.app->run(log);
        return x;
    }();
    return r;
}

TEST(MrptWorkflow, SceneFileHoldsPathLandmarksTrianglesAndLayers)
{
    const auto& r = run();
    mrpt::opengl::COpenGLScene scene;
    ASSERT_TRUE(scene.loadFromFile(r.out + "/map.3Dscene"));
    for (const char* name : {"path", "landmarks", "ltr_triangles", "occupancy", "points"})
        EXPECT_TRUE(scene.getByName(name)) << name;
    const auto& slam = r.app->slam();
    const auto path = std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(scene.getByName("path"));
    ASSERT_TRUE(path);
    EXPECT_EQ(path->getLineCount() + 1, slam.path().size());
    const auto tri = std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(scene.getByName("ltr_triangles"));
    ASSERT_TRUE(tri);
    EXPECT_EQ(tri->getLineCount(), 3 * slam.partition()->size());
    const auto lms = std::dynamic_pointer_cast<mrpt::opengl::CSetOfObjects>(scene.getByName("landmarks"));
    ASSERT_TRUE(lms);
    EXPECT_EQ(lms->size(), hymm::app::hybridMetricMap(slam).landmarks().size() + 1);  // ellipses + means
}

TEST(MrptWorkflow, SimplemapHoldsAKeyframePerPathSample)
{
    const auto& r = run();
    const auto& slam = r.app->slam();
    mrpt::maps::CSimpleMap sm;
    ASSERT_TRUE(sm.loadFromFile(r.out + "/map.simplemap"));
    ASSERT_EQ(sm.size(), slam.path().size());
    size_t with_scan = 0;
    for (size_t i = 0; i < sm.size(); ++i)
    {
        const auto& [pose, sf] = sm.get(i);
        const auto g = std::dynamic_pointer_cast<mrpt::poses::CPose3DPDFGaussian>(pose);
        ASSERT_TRUE(g) << i;
        const auto& s = slam.path()[i];
        EXPECT_NEAR(g->mean.x(), s.pose.x(), 1e-9);
        EXPECT_NEAR(g->mean.y(), s.pose.y(), 1e-9);
        EXPECT_NEAR(g->mean.yaw(), s.pose.z(), 1e-9);
        // CPose3D order (x y z yaw pitch roll): the 2D covariance sits in rows 0, 1, 3.
        EXPECT_NEAR(g->cov(0, 0), s.cov(0, 0), 1e-12);
        EXPECT_NEAR(g->cov(1, 1), s.cov(1, 1), 1e-12);
        EXPECT_NEAR(g->cov(3, 3), s.cov(2, 2), 1e-12);
        EXPECT_NEAR(g->cov(0, 3), s.cov(0, 2), 1e-12);
        if (sf->getObservationByClass<mrpt::obs::CObservation2DRangeScan>()) ++with_scan;
    }
    EXPECT_GT(with_scan, sm.size() / 2);
}

// Occupied / free / unknown by MRPT's convention (cell value = P(free)).
TEST(MrptWorkflow, RunRawlogHoldsTheInputWithTheEstimatedPoses)
{
    const auto& r = run();
    mrpt::obs::CRawlog log;
    ASSERT_TRUE(log.loadFromRawLogFile(r.out + "/run.rawlog"));
    const auto& path = r.app->slam().path();
    ASSERT_EQ(path.size(), 469u);
    // The input's odometry at each frame: its actions' increments composed from the origin.
    mrpt::obs::CRawlog input;
    ASSERT_TRUE(input.loadFromRawLogFile(kSrc + "/rawlogs/ch3_objects.rawlog"));
    std::vector<mrpt::poses::CPose2D> odometry;
    mrpt::poses::CPose2D odo;
    for (size_t i = 0; i < input.size(); ++i)
        if (input.getType(i) == mrpt::obs::CRawlog::etActionCollection)
        {
            if (auto mov = input.getAsAction(i)->getBestMovementEstimation()) odo = odo + mov->poseChange->getMeanVal();
        }
        else if (input.getType(i) == mrpt::obs::CRawlog::etSensoryFrame)
            odometry.push_back(odo);
    ASSERT_EQ(odometry.size(), path.size());
    // Observation format (MRPT 2's default): pose, odometry, laser scan, landmarks per frame.
    ASSERT_EQ(log.size(), 4 * path.size());
    size_t poses = 0, odometries = 0, scans = 0, landmarks = 0;
    for (size_t i = 0; i < log.size(); ++i)
    {
        ASSERT_EQ(log.getType(i), mrpt::obs::CRawlog::etObservation) << i;
        const auto o = log.getAsObservation(i);
        if (const auto p = std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(o))
        {
            ASSERT_EQ(i % 4, 0u);
            EXPECT_EQ(p->sensorLabel, "HYMM_POSE");
            const auto& s = path.at(poses);
            EXPECT_EQ(p->pose.mean.x(), s.pose.x());
            EXPECT_EQ(p->pose.mean.y(), s.pose.y());
            EXPECT_NEAR(p->pose.mean.yaw(), s.pose.z(), 1e-12);
            EXPECT_NEAR(p->pose.cov(0, 0), s.cov(0, 0), 1e-15);
            EXPECT_NEAR(p->pose.cov(3, 3), s.cov(2, 2), 1e-15);
            EXPECT_NEAR(mrpt::Clock::toDouble(p->timestamp), s.t, 1e-6);
            ++poses;
        }
        else if (const auto d = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o))
        {
            ASSERT_EQ(i % 4, 1u);
            EXPECT_EQ(d->sensorLabel, "ODOMETRY");
            const auto& want = odometry.at(odometries);
            EXPECT_NEAR(d->odometry.x(), want.x(), 1e-9);
            EXPECT_NEAR(d->odometry.y(), want.y(), 1e-9);
            EXPECT_NEAR(d->odometry.phi(), want.phi(), 1e-12);
            EXPECT_NEAR(mrpt::Clock::toDouble(d->timestamp), path.at(odometries).t, 1e-6);
            ++odometries;
        }
        else if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o))
            ++scans;
        else if (std::dynamic_pointer_cast<mrpt::obs::CObservationBearingRange>(o))
            ++landmarks;
    }
    EXPECT_EQ(poses, path.size());
    EXPECT_EQ(odometries, path.size());
    EXPECT_EQ(scans, path.size());
    EXPECT_EQ(landmarks, path.size());
}

TEST(MrptWorkflow, GridMrptBuildsFromTheSimplemapAgreesWithOurs)
{
    const auto& r = run();
    mrpt::maps::CSimpleMap sm;
    ASSERT_TRUE(sm.loadFromFile(r.out + "/map.simplemap"));
    const auto ours = hymm::dense::CHybridMetricMap::loadFromFile(r.out + "/map.hymm");
    const auto& g_ours = ours->renderedOccupancy();
    const double res = g_ours.getResolution();

    // What observations2map does with an occupancy grid: insert every scan at its keyframe.
    mrpt::maps::COccupancyGridMap2D g_mrpt(g_ours.getXMin(), g_ours.getXMax(), g_ours.getYMin(),
                                           g_ours.getYMax(), static_cast<float>(res));
    g_mrpt.insertionOptions.maxDistanceInsertion = static_cast<float>(ours->dense().options().max_range_m);
    g_mrpt.loadFromSimpleMap(sm);

    hymm::testing::expectGridsAgree("grid", hymm::testing::compareGrids(g_ours, g_mrpt));
}

// MRPT's particle filter on the saved hybrid map, fed a simulated run of the same world.
struct LocalisationScore
{
    double mean_error_m = 0;  // over the frames after the first 20 (convergence)
    double max_error_m = 0;
    double initial_error_m = 0;  // of the initial particle mean
    double mean_nees = 0;        // position NEES (2 DOF) of the particle set, same frames
};

LocalisationScore localise(const mrpt::maps::CMetricMap::Ptr& map, long seed, size_t frames)
{
    auto s = hymm::sim::Scenario::fromFile(kSrc + "/configs/sim/ch3_objects.ini");
    s.run.seed = seed;
    hymm::sim::Simulator sim(s);
    mrpt::random::getRandomGenerator().randomize(static_cast<uint32_t>(seed));

    mrpt::slam::CMonteCarloLocalization2D pdf(600);
    pdf.options.metricMap = map;
    // The start (the origin of the map frame) is known to within a 2 m x 2 m x 20 deg box
    // whose centre is off by (0.7, -0.7) m and 5 deg.
    pdf.resetUniform(-0.3, 1.7, -1.7, 0.3, -5 * M_PI / 180, 15 * M_PI / 180, 600);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.PF_algorithm = mrpt::bayes::CParticleFilter::pfStandardProposal;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    pf.m_options.adaptiveSampleSize = false;

    LocalisationScore score;
    score.initial_error_m = pdf.getMeanVal().norm();
    double sum = 0;
    size_t n = 0;
    hymm::sim::SimFrame f;
    for (size_t k = 0; k < frames && sim.next(f); ++k)
    {
        // The odometry increment with the simulator's covariance, inflated (x4 variance)
        // for what the map's own error adds.
        mrpt::obs::CActionRobotMovement2D mov;
        mov.estimationMethod = mrpt::obs::CActionRobotMovement2D::emOdometry;
        const mrpt::poses::CPose2D inc(f.odometry_mean[0], f.odometry_mean[1], f.odometry_mean[2]);
        mov.rawOdometryIncrementReading = inc;
        mov.poseChange = mrpt::poses::CPosePDFGaussian::Create(
            inc, mrpt::math::CMatrixDouble33(Eigen::Matrix3d(4.0 * f.odometry_cov)));
        mrpt::obs::CActionCollection acts;
        acts.insert(mov);
        mrpt::obs::CSensoryFrame sf;
        if (f.scan) sf.insert(f.scan);
        pf.executeOn(pdf, &acts, &sf);
        const auto [cov, est] = pdf.getCovarianceAndMean();
        const Eigen::Vector2d e(est.x() - f.true_pose.x(), est.y() - f.true_pose.y());
        const double err = e.norm();
        if (k >= 20)
        {
            const Eigen::Matrix2d p = cov.asEigen().topLeftCorner<2, 2>();
            score.mean_nees += e.dot(p.ldlt().solve(e));
            sum += err;
            ++n;
            score.max_error_m = std::max(score.max_error_m, err);
        }
    }
    score.mean_error_m = n ? sum / static_cast<double>(n) : NAN;
    score.mean_nees = n ? score.mean_nees / static_cast<double>(n) : NAN;
    return score;
}

TEST(MrptWorkflow, MonteCarloLocalisationOnTheSavedHybridMap)
{
    const auto& r = run();
    hymm::dense::registerHybridMetricMap();
    mrpt::config::CConfigFileMemory ini("[MAP]\nHybridMetricMap_count = 1\n[MAP_HybridMetricMap_00]\nmap_file = " +
                                        r.out + "/map.hymm\n");
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(ini, "MAP");
    auto map = mrpt::maps::CMultiMetricMap::Create();
    map->setListOfMaps(inits);
    ASSERT_TRUE(map->mapByClass<hymm::dense::CHybridMetricMap>());

    // The same filter on the grid MRPT builds from map.simplemap (scans at the filtered
    // path estimates): what localising on the keyframes alone gives.
    mrpt::maps::CSimpleMap sm;
    ASSERT_TRUE(sm.loadFromFile(r.out + "/map.simplemap"));
    const auto& ours = *map->mapByClass<hymm::dense::CHybridMetricMap>();
    auto grid = mrpt::maps::COccupancyGridMap2D::Create(
        ours.renderedOccupancy().getXMin(), ours.renderedOccupancy().getXMax(),
        ours.renderedOccupancy().getYMin(), ours.renderedOccupancy().getYMax(),
        ours.renderedOccupancy().getResolution());
    grid->insertionOptions.maxDistanceInsertion = static_cast<float>(ours.dense().options().max_range_m);
    grid->loadFromSimpleMap(sm);

    double sum_hymm = 0, sum_grid = 0;
    int n = 0;
    for (long seed : {11, 12, 13, 14, 15})
    {
        const auto sc = localise(map, seed, 240);
        const auto sg = localise(grid, seed, 240);
        std::cout << "[pf] seed " << seed << ": initial " << sc.initial_error_m << " m; on map.hymm mean "
                  << sc.mean_error_m << " m, max " << sc.max_error_m << " m, position NEES " << sc.mean_nees
                  << "; on the simplemap grid mean " << sg.mean_error_m << " m, max " << sg.max_error_m
                  << " m, NEES " << sg.mean_nees << "\n";
        EXPECT_GT(sc.initial_error_m, 0.5) << seed;
        EXPECT_LT(sc.mean_error_m, 0.4) << seed;
        EXPECT_LT(sc.max_error_m, 1.0) << seed;
        // The particle set is overconfident on the hybrid map (measured 6.5-8.9 against a
        // chi-square mean of 2 since map.hymm holds the fallback tiles, 4.8-5.7 without
        // them: the map's own error is not in MRPT's sensor model, and the tiles' returns
        // sharpen the likelihood field), but far less than on the keyframes' grid (60-130).
        EXPECT_LT(sc.mean_nees, 12.0) << seed;
        sum_hymm += sc.mean_error_m;
        sum_grid += sg.mean_error_m;
        ++n;
    }
    std::cout << "[pf] mean over seeds: map.hymm " << sum_hymm / n << " m, simplemap grid " << sum_grid / n << " m\n";
    // The hybrid map is drawn at the final landmark estimates; the keyframes carry the
    // filtered poses of their time, before later corrections (thesis Example 3.2).
    EXPECT_LT(sum_hymm, 0.6 * sum_grid);
}

}  // namespace
