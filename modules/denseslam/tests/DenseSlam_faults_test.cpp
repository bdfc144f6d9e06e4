// Faults in well-formed rawlogs: the first frames of the bundled chapter-3 rawlog with
// one fault injected each. Every fault is counted and handled; no NaN reaches the state.
#include <gtest/gtest.h>
#include <hymm/core/config_utils.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/io/RawlogReader.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <vector>

namespace
{
using hymm::denseslam::DenseSlam;
using hymm::io::RawlogEntry;

const std::string kRoot = HYMM_SOURCE_DIR;
constexpr size_t kFrames = 120;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A fresh copy of the first kFrames action/frame pairs (re-read: each test mutates it).
std::vector<RawlogEntry> loadEntries()
{
    hymm::io::RawlogReader r(kRoot + "/rawlogs/ch3_objects.rawlog");
    std::vector<RawlogEntry> out;
    RawlogEntry e;
    size_t frames = 0;
    while (frames < kFrames && r.next(e))
    {
        out.push_back(e);
        if (e.frame) ++frames;
    }
    return out;
}

DenseSlam makeSlam()
{
    return DenseSlam::fromConfig(*hymm::core::openConfigFile(kRoot + "/configs/ch3_slam.ini"));
}

DenseSlam run(const std::vector<RawlogEntry>& entries)
{
    auto slam = makeSlam();
    for (const auto& e : entries) slam.processEntry(e);
    return slam;
}

// Indices of the entries holding frames, in order.
std::vector<size_t> frameIndices(const std::vector<RawlogEntry>& entries)
{
    std::vector<size_t> idx;
    for (size_t i = 0; i < entries.size(); ++i)
        if (entries[i].frame) idx.push_back(i);
    return idx;
}

template <class T>
std::shared_ptr<T> first(const RawlogEntry& e)
{
    return e.frame->getObservationByClass<T>();
}

mrpt::poses::CPosePDFGaussian& increment(const RawlogEntry& e)
{
    auto mov = e.actions->getBestMovementEstimation();
    return dynamic_cast<mrpt::poses::CPosePDFGaussian&>(*mov->poseChange);
}

// The state stays finite, the covariance symmetric positive semi-definite, the path finite.
void expectHealthy(const DenseSlam& slam, size_t path_samples)
{
    const auto& x = slam.ekf().mean();
    const auto& P = slam.ekf().cov();
    ASSERT_TRUE(x.allFinite());
    ASSERT_TRUE(P.allFinite());
    EXPECT_LT((P - P.transpose()).cwiseAbs().maxCoeff(), 1e-9 * (1 + P.cwiseAbs().maxCoeff()));
    const Eigen::MatrixXd S = 0.5 * (P + P.transpose());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S).eigenvalues().minCoeff(), -1e-9);
    EXPECT_EQ(slam.path().size(), path_samples);
    for (const auto& s : slam.path())
    {
        ASSERT_TRUE(s.pose.allFinite());
        ASSERT_TRUE(s.cov.allFinite());
        ASSERT_TRUE(std::isfinite(s.t));
    }
    EXPECT_GT(slam.ekf().numLandmarks(), 3u);
}

class DenseSlamFaults : public ::testing::Test
{
protected:
    static void SetUpTestSuite()
    {
        const auto clean = run(loadEntries());
        clean_stats_ = new DenseSlam::Stats(clean.stats());
        clean_final_ = new Eigen::Vector3d(clean.ekf().vehiclePose());
        clean_path_ = clean.path().size();
    }
    static void TearDownTestSuite()
    {
        delete clean_stats_;
        delete clean_final_;
    }
    static DenseSlam::Stats* clean_stats_;
    static Eigen::Vector3d* clean_final_;
    static size_t clean_path_;
};
DenseSlam::Stats* DenseSlamFaults::clean_stats_ = nullptr;
Eigen::Vector3d* DenseSlamFaults::clean_final_ = nullptr;
size_t DenseSlamFaults::clean_path_ = 0;

TEST_F(DenseSlamFaults, CleanRunHasNoFaultCounts)
{
    EXPECT_EQ(clean_path_, kFrames);
    EXPECT_EQ(clean_stats_->odometry_invalid, 0u);
    EXPECT_EQ(clean_stats_->frames_duplicate, 0u);
    EXPECT_EQ(clean_stats_->frames_without_odometry, 0u);
    EXPECT_EQ(clean_stats_->time_backwards, 0u);
    EXPECT_EQ(clean_stats_->time_repeated, 0u);
    EXPECT_EQ(clean_stats_->scans_without_valid_beam, 0u);
    EXPECT_TRUE(clean_stats_->unsupported.empty());
}

TEST_F(DenseSlamFaults, NonFiniteOdometryIsSkippedAndCounted)
{
    auto entries = loadEntries();
    const auto f = frameIndices(entries);
    increment(entries[f[30] - 1]).mean.x(kNaN);
    increment(entries[f[60] - 1]).cov(2, 2) = kInf;
    increment(entries[f[90] - 1]).mean.phi(-kInf);
    const auto slam = run(entries);
    EXPECT_EQ(slam.stats().odometry_invalid, 3u);
    EXPECT_EQ(slam.stats().predictions, clean_stats_->predictions - 3);
    EXPECT_EQ(slam.stats().frames_without_odometry, 3u);
    expectHealthy(slam, kFrames);
    // Skipping is exactly a rawlog without those three actions.
    std::vector<RawlogEntry> without;
    for (size_t i = 0; i < entries.size(); ++i)
        if (i != f[30] - 1 && i != f[60] - 1 && i != f[90] - 1) without.push_back(entries[i]);
    const auto ref = run(without);
    EXPECT_EQ(ref.stats().odometry_invalid, 0u);
    EXPECT_LT((slam.ekf().vehiclePose() - ref.ekf().vehiclePose()).norm(), 1e-12);
    EXPECT_EQ(slam.ekf().numLandmarks(), ref.ekf().numLandmarks());
}

TEST_F(DenseSlamFaults, NonFiniteRangesAreSkippedAndCounted)
{
    auto entries = loadEntries();
    const auto f = frameIndices(entries);
    size_t poisoned_beams = 0;
    for (size_t k = 10; k < 20; ++k)
    {
        auto br = first<mrpt::obs::CObservationBearingRange>(entries[f[k]]);
        ASSERT_TRUE(br && !br->sensedData.empty());
        br->sensedData[0].range = k % 2 ? static_cast<float>(kNaN) : static_cast<float>(kInf);
        br->sensedData.back().yaw = static_cast<float>(kNaN);
        auto scan = first<mrpt::obs::CObservation2DRangeScan>(entries[f[k]]);
        ASSERT_TRUE(scan);
        for (size_t i = 0; i < scan->getScanSize(); i += 7)
            if (scan->getScanRangeValidity(i))
            {
                scan->setScanRange(i, k % 2 ? static_cast<float>(kNaN) : static_cast<float>(kInf));
                ++poisoned_beams;
            }
    }
    const auto slam = run(entries);
    EXPECT_GE(slam.stats().skipped_invalid, clean_stats_->skipped_invalid + 10);
    EXPECT_EQ(slam.stats().failed_readings, clean_stats_->failed_readings + poisoned_beams);
    expectHealthy(slam, kFrames);
}

TEST_F(DenseSlamFaults, ZeroRangesAreSkippedAndCounted)
{
    auto entries = loadEntries();
    const auto f = frameIndices(entries);
    size_t zeroed_beams = 0, zeroed_readings = 0;
    for (size_t k = 40; k < 50; ++k)
    {
        auto br = first<mrpt::obs::CObservationBearingRange>(entries[f[k]]);
        for (auto& m : br->sensedData) m.range = 0.f;
        zeroed_readings += br->sensedData.size();
        auto scan = first<mrpt::obs::CObservation2DRangeScan>(entries[f[k]]);
        for (size_t i = 0; i < scan->getScanSize(); ++i)
            if (scan->getScanRangeValidity(i))
            {
                scan->setScanRange(i, 0.f);
                ++zeroed_beams;
            }
    }
    ASSERT_GT(zeroed_readings, 0u);
    const auto slam = run(entries);
    EXPECT_EQ(slam.stats().skipped_invalid, clean_stats_->skipped_invalid + zeroed_readings);
    EXPECT_EQ(slam.stats().failed_readings, clean_stats_->failed_readings + zeroed_beams);
    expectHealthy(slam, kFrames);
}

TEST_F(DenseSlamFaults, ScansWithEveryBeamInvalidAreCounted)
{
    auto entries = loadEntries();
    const auto f = frameIndices(entries);
    for (size_t k = 70; k < 85; ++k)
    {
        auto scan = first<mrpt::obs::CObservation2DRangeScan>(entries[f[k]]);
        for (size_t i = 0; i < scan->getScanSize(); ++i) scan->setScanRangeValidity(i, false);
    }
    const auto slam = run(entries);
    EXPECT_EQ(slam.stats().scans_without_valid_beam, 15u);
    EXPECT_LT(slam.stats().returns_stored, clean_stats_->returns_stored);
    expectHealthy(slam, kFrames);
}

TEST_F(DenseSlamFaults, RepeatedAndBackwardTimestampsAreCounted)
{
    auto entries = loadEntries();
    const auto f = frameIndices(entries);
    const auto stampOf = [&](size_t k) { return entries[f[k]].frame->begin()->get()->timestamp; };
    const auto restamp = [&](size_t k, mrpt::Clock::time_point t)
    {
        for (auto& o : *entries[f[k]].frame) o->timestamp = t;
    };
    restamp(20, stampOf(19));                                        // repeated
    restamp(50, stampOf(40));                                        // backwards
    restamp(80, stampOf(79) - std::chrono::milliseconds(1));         // backwards
    const auto slam = run(entries);
    EXPECT_EQ(slam.stats().time_repeated, 1u);
    EXPECT_EQ(slam.stats().time_backwards, 2u);
    EXPECT_EQ(slam.stats().frames_duplicate, 0u) << "odometry in between: not a duplicate";
    expectHealthy(slam, kFrames);
}

TEST_F(DenseSlamFaults, DuplicatedEntriesAreSkippedAndCounted)
{
    auto entries = loadEntries();
    const auto f = frameIndices(entries);
    // Frame 25 twice in a row, and frame 64 three times.
    entries.insert(entries.begin() + static_cast<std::ptrdiff_t>(f[64]), 2, entries[f[64]]);
    entries.insert(entries.begin() + static_cast<std::ptrdiff_t>(f[25]), entries[f[25]]);
    const auto slam = run(entries);
    EXPECT_EQ(slam.stats().frames_duplicate, 3u);
    expectHealthy(slam, kFrames);
    // Skipped, so the run is the clean one.
    EXPECT_EQ(slam.stats().observations, clean_stats_->observations);
    EXPECT_LT((slam.ekf().vehiclePose() - *clean_final_).norm(), 1e-9);
}

TEST_F(DenseSlamFaults, FramesWithoutOdometryAreCounted)
{
    auto entries = loadEntries();
    std::vector<RawlogEntry> kept;
    size_t frames = 0, dropped = 0;
    for (const auto& e : entries)
    {
        if (e.frame) ++frames;
        // Drop the actions before frames 50..57 (the vehicle moves ~0.3 m per frame).
        if (e.actions && frames >= 50 && frames < 58)
        {
            ++dropped;
            continue;
        }
        kept.push_back(e);
    }
    ASSERT_EQ(dropped, 8u);
    const auto slam = run(kept);
    EXPECT_EQ(slam.stats().frames_without_odometry, 8u);
    expectHealthy(slam, kFrames);
}

TEST_F(DenseSlamFaults, FiftyMetreKidnapKeepsTheStateFinite)
{
    // Odometry reports a 50 m jump the vehicle did not make: the observations then match
    // nothing near the predicted pose, so they are gated out or start new landmarks.
    auto entries = loadEntries();
    const auto f = frameIndices(entries);
    auto& inc = increment(entries[f[60] - 1]);
    inc.mean.x(inc.mean.x() + 50.0);
    const auto slam = run(entries);
    expectHealthy(slam, kFrames);
    const auto& s = slam.stats();
    EXPECT_GT(s.created + s.rejected_gate, clean_stats_->created + clean_stats_->rejected_gate);
    EXPECT_GT((slam.ekf().vehiclePose().head<2>() - clean_final_->head<2>()).norm(), 10.0)
        << "a 50 m odometry error cannot be undone by landmarks out of the gate";
}

TEST_F(DenseSlamFaults, NonFiniteSensorPosesAreSkippedAndCounted)
{
    // A corrupt sensor pose (NaN, inf, or a mount kilometres off the vehicle) would put
    // every reading of that observation at NaN: the observation is skipped, not fused.
    auto entries = loadEntries();
    const auto f = frameIndices(entries);
    size_t poisoned = 0;
    for (size_t k = 30; k < 40; ++k)
    {
        auto br = first<mrpt::obs::CObservationBearingRange>(entries[f[k]]);
        auto scan = first<mrpt::obs::CObservation2DRangeScan>(entries[f[k]]);
        ASSERT_TRUE(br && scan);
        const double bad = k % 3 == 0 ? kNaN : (k % 3 == 1 ? kInf : 1e6);
        br->sensorLocationOnRobot.x(bad);
        auto sp = scan->sensorPose;
        sp.setYawPitchRoll(k % 2 ? kNaN : sp.yaw(), sp.pitch(), sp.roll());
        if (k % 2 == 0) sp.y(bad);
        scan->sensorPose = sp;
        poisoned += 2;
    }
    const auto slam = run(entries);
    EXPECT_EQ(slam.stats().observations_invalid_geometry, poisoned);
    EXPECT_EQ(clean_stats_->observations_invalid_geometry, 0u);
    expectHealthy(slam, kFrames);
}

TEST_F(DenseSlamFaults, AbsurdCovariancesKeepTheStateFinite)
{
    // Finite but absurd covariances (odometry 1e300 m^2, a landmark reading's negative or
    // 1e300 variances) must not overflow the filter into inf / NaN.
    auto entries = loadEntries();
    const auto f = frameIndices(entries);
    size_t poisoned = 0;
    for (size_t k = 40; k < 50; ++k)
    {
        auto& inc = increment(entries[f[k] - 1]);
        inc.cov(0, 0) = k % 2 ? 1e300 : -1.0;
        auto br = first<mrpt::obs::CObservationBearingRange>(entries[f[k]]);
        ASSERT_TRUE(br && !br->sensedData.empty());
        br->validCovariances = true;
        for (auto& m : br->sensedData)
        {
            m.covariance.setZero();
            m.covariance(1, 1) = m.covariance(2, 2) = 1e-4;
            m.covariance(0, 0) = k % 2 ? 1e300 : -1.0;
            ++poisoned;
        }
    }
    const auto slam = run(entries);
    EXPECT_EQ(slam.stats().odometry_invalid, 10u);
    EXPECT_EQ(slam.stats().skipped_invalid, clean_stats_->skipped_invalid + poisoned);
    expectHealthy(slam, kFrames);
}

TEST_F(DenseSlamFaults, NonFiniteScanGeometryKeepsEveryLayerFinite)
{
    // A scan whose aperture or maximum range is NaN / inf places its beams at NaN angles:
    // with every dense layer, the delayed store and the motion layers on (as the rawlog
    // fuzz target runs), nothing of it may reach the filter or a region lookup.
    // In memory: a CConfigFile written to would save itself over the shipped config.
    std::ifstream in(kRoot + "/configs/ch3_slam.ini");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(text.empty());
    auto cfg = std::make_unique<mrpt::config::CConfigFileMemory>(text);
    cfg->write("DenseSlam", "dense_layers", "points,occupancy,particles,sog,property");
    cfg->write("DelayedDenseStore", "enabled", "true");
    cfg->write("DynamicSlam", "enabled", "true");
    auto entries = loadEntries();
    const auto f = frameIndices(entries);
    for (size_t k = 20; k < 40; ++k)
    {
        auto scan = first<mrpt::obs::CObservation2DRangeScan>(entries[f[k]]);
        ASSERT_TRUE(scan);
        if (k % 2)
            scan->aperture = static_cast<float>(k % 4 == 1 ? kNaN : kInf);
        else
            scan->maxRange = static_cast<float>(k % 4 == 0 ? kNaN : kInf);
    }
    auto slam = DenseSlam::fromConfig(*cfg);
    for (const auto& e : entries) slam.processEntry(e);
    slam.refreshRegions();
    EXPECT_EQ(slam.stats().observations_invalid_geometry, 20u);
    expectHealthy(slam, kFrames);
}

}  // namespace
