// hymm-slam --save-state / --resume (SlamApp, slam_state.h) on the bundled chapter-3
// rawlog with every dense layer, the classic grid, virtual landmarks, the delayed store,
// the fallback tiles and the motion layers (resume_layers.ini): a run cut in two and resumed writes the
// uninterrupted run's files byte for byte (timing lines aside, as scripts/check-outputs
// compares), from the same rawlog and from a second rawlog holding the rest, also from the
// periodic save (--save-state-every) of a run that failed later; a foreign,
// other-version, truncated or corrupt state and another config are clear errors before
// anything is written, as is --save-state-every without --save-state. Scan landmarks with the
// scan odometry and high-level landmarks resume too.
#include "ch3_sample.h"
#include "slam_app_files.h"

#include <gtest/gtest.h>
#include <hymm/app/slam_outputs.h>
#include <hymm/app/SlamApp.h>
#include <hymm/app/slam_state.h>
#include <hymm/denseslam/LandmarkSources.h>
#include <hymm/hll/HighLevelLandmarks.h>
#include <hymm/io/RawlogReader.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/serialization/CArchive.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace
{
namespace fs = std::filesystem;
using hymm::app::SlamApp;
using hymm::test::readFile;
using hymm::test::TempDir;

const std::string kSrc = HYMM_SOURCE_DIR;
const std::string& kRawlog = hymm::test::kCh3Rawlog;
const std::string kConfig = kSrc + "/tests/slam_app/resume_layers.ini";
// The run is cut after entry kCut of the first kEnd (a few seconds in all).
constexpr size_t kCut = 150;
constexpr size_t kEnd = 260;

SlamApp::Args argsFor(const std::string& out) { return hymm::test::ch3SampleArgs(kConfig, out); }

// As scripts/check-outputs --compare: the lines carrying run times are left out. Plain string
// search rather than std::regex: GCC 12's <regex> trips -Wmaybe-uninitialized under the
// sanitizer build's -Werror.
bool carriesTiming(const std::string& line)
{
    if (line.rfind("run time", 0) == 0) return true;
    for (const char* word : {"\"run_seconds\"", "seconds", "elapsed"})
        if (line.find(word) != std::string::npos) return true;
    // "<number> s" followed by a non-word character or the end of the line.
    for (size_t at = line.find(" s"); at != std::string::npos; at = line.find(" s", at + 1))
    {
        const bool numberBefore =
            at > 0 && (std::isdigit(static_cast<unsigned char>(line[at - 1])) || line[at - 1] == '.');
        const size_t after = at + 2;
        const bool wordEnds = after == line.size() ||
                              !(std::isalnum(static_cast<unsigned char>(line[after])) || line[after] == '_');
        if (numberBefore && wordEnds) return true;
    }
    return false;
}

std::string withoutTimings(const std::string& text)
{
    std::istringstream in(text);
    std::string line, out;
    while (std::getline(in, line))
        if (!carriesTiming(line)) out += line + "\n";
    return out;
}

// Every file of `a` equals that of `b` (timing.csv and the manifest aside); returns the
// number compared.
size_t expectSameOutputs(const fs::path& a, const fs::path& b)
{
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(a))
    {
        const std::string name = e.path().filename().string();
        if (name == "timing.csv" || name == ".hymm-outputs") continue;
        ++n;
        if (!fs::exists(b / name))
        {
            ADD_FAILURE() << "missing after resume: " << name;
            continue;
        }
        const bool text = name == "summary.txt" || e.path().extension() == ".json";
        const std::string x = readFile(e.path()), y = readFile(b / name);
        if (text)
            EXPECT_EQ(withoutTimings(x), withoutTimings(y)) << name;
        else
            EXPECT_TRUE(x == y) << name << " differs after resume";
    }
    size_t m = 0;
    for (const auto& e : fs::directory_iterator(b))
        m += e.path().filename() != "timing.csv" && e.path().filename() != ".hymm-outputs";
    EXPECT_EQ(n, m) << "the resumed run wrote other files";
    return n;
}

// Entries [from, to) of the sample as a rawlog of their own; `bad_tail` adds an object
// that is no rawlog entry after them.
void writeEntries(const std::string& path, size_t from, size_t to, bool bad_tail = false)
{
    hymm::io::RawlogReader r(kRawlog);
    mrpt::io::CFileGZOutputStream f;
    ASSERT_TRUE(f.open(path, 1));
    auto ar = mrpt::serialization::archiveFrom(f);
    hymm::io::RawlogEntry e;
    while (r.entriesRead() < to && r.next(e))
        if (r.entriesRead() > from)
        {
            if (e.actions) ar << *e.actions;
            if (e.frame) ar << *e.frame;
            if (e.observation) ar << *e.observation;
        }
    if (bad_tail) ar << mrpt::poses::CPose2D(1, 2, 0.3);
}

class Resume : public ::testing::Test
{
protected:
    static void SetUpTestSuite()
    {
        dir_ = new TempDir("hymm_resume_test_");
        fs::create_directories(dir_->path);
    }

    // The uninterrupted run ("full") and the first part with its state ("first",
    // cut.state), each made once per test process and only by the tests that read it:
    // ctest runs every test in a process of its own, and under the sanitizers each run
    // costs tens of seconds.
    static void needFull()
    {
        static bool made = false;
        if (made) return;
        SlamApp::Args full = argsFor(*dir_ / "full");
        full.stop_after = kEnd;
        SlamApp(full).run(std::cerr);
        made = true;
    }
    static void needCut()
    {
        static bool made = false;
        if (made) return;
        SlamApp::Args first = argsFor(*dir_ / "first");
        first.stop_after = kCut;
        first.save_state = *dir_ / "cut.state";
        first.save_state_every = 50;  // the periodic saves leave the run as it is
        SlamApp app(first);
        app.run(std::cerr);
        // The cut falls where every part of the state holds something.
        const auto& slam = app.slam();
        stored_at_cut_ = slam.delayedStore()->numStoredPoints();
        tiles_at_cut_ = slam.hybridMap()->fallbackTiles();
        regions_at_cut_ = slam.partition()->size();
        virtual_at_cut_ = slam.virtualLandmarkIds().size();
        motion_regions_at_cut_ = slam.motionHook()->detector().size();
        slow_differencings_at_cut_ = slam.motionHook()->stats().slow_differencings;
        made = true;
    }
    static void TearDownTestSuite() { delete dir_; }

    /** Runs the sample under `config` to entry `end`, then cut after `cut` with a saved
     *  state (`at_cut` checks what the first part holds) and resumed to `end`: the
     *  outputs must be the uninterrupted run's. */
    static void expectCutResumes(const std::string& config, size_t cut, size_t end, const std::string& tag,
                                 const std::function<void(const hymm::denseslam::DenseSlam&)>& at_cut)
    {
        SlamApp::Args full = hymm::test::ch3SampleArgs(config, *dir_ / (tag + "_full"));
        full.stop_after = end;
        SlamApp(full).run(std::cerr);
        SlamApp::Args first = hymm::test::ch3SampleArgs(config, *dir_ / (tag + "_first"));
        first.stop_after = cut;
        first.save_state = *dir_ / (tag + ".state");
        SlamApp app(first);
        app.run(std::cerr);
        at_cut(app.slam());
        EXPECT_NE(readFile(fs::path(*dir_ / (tag + "_first")) / "path.tum"),
                  readFile(fs::path(*dir_ / (tag + "_full")) / "path.tum"));
        SlamApp::Args second = hymm::test::ch3SampleArgs(config, *dir_ / (tag + "_resumed"));
        second.resume = first.save_state;
        second.stop_after = end;
        SlamApp(second).run(std::cerr);
        EXPECT_GE(expectSameOutputs(*dir_ / (tag + "_full"), *dir_ / (tag + "_resumed")), 8u);
    }

    static TempDir* dir_;
    static size_t stored_at_cut_, tiles_at_cut_, regions_at_cut_, virtual_at_cut_;
    static size_t motion_regions_at_cut_, slow_differencings_at_cut_;
};
TempDir* Resume::dir_ = nullptr;
size_t Resume::stored_at_cut_ = 0, Resume::tiles_at_cut_ = 0, Resume::regions_at_cut_ = 0,
       Resume::virtual_at_cut_ = 0, Resume::motion_regions_at_cut_ = 0,
       Resume::slow_differencings_at_cut_ = 0;

TEST_F(Resume, StateAtTheCutHoldsEveryDenseComponent)
{
    needFull();
    needCut();
    EXPECT_GT(stored_at_cut_, 0u);
    EXPECT_GT(tiles_at_cut_, 0u);
    EXPECT_GT(regions_at_cut_, 0u);
    EXPECT_GT(virtual_at_cut_, 0u);
    EXPECT_GT(motion_regions_at_cut_, 0u);
    EXPECT_GT(slow_differencings_at_cut_, 0u);
    // The first part's results are not the whole run's: the comparison below means something.
    EXPECT_NE(readFile(fs::path(*dir_ / "first") / "path.tum"), readFile(fs::path(*dir_ / "full") / "path.tum"));
}

TEST_F(Resume, SameRawlogContinuesAfterTheCutToIdenticalOutputs)
{
    needFull();
    needCut();
    SlamApp::Args second = argsFor(*dir_ / "resumed");
    second.resume = *dir_ / "cut.state";
    second.stop_after = kEnd;
    SlamApp(second).run(std::cerr);
    EXPECT_GE(expectSameOutputs(*dir_ / "full", *dir_ / "resumed"), 20u);
}

TEST_F(Resume, SecondRawlogContinuesFromItsStartToIdenticalOutputs)
{
    needFull();
    needCut();
    writeEntries(*dir_ / "rest.rawlog", kCut, kEnd);
    SlamApp::Args second = argsFor(*dir_ / "resumed2");
    second.rawlog = *dir_ / "rest.rawlog";
    second.resume = *dir_ / "cut.state";
    second.save_state = *dir_ / "end.state";
    SlamApp(second).run(std::cerr);
    EXPECT_GE(expectSameOutputs(*dir_ / "full", *dir_ / "resumed2"), 20u);
    // The state saved after the second rawlog resumes too (nothing left to read: the
    // results are the same again).
    SlamApp::Args third = argsFor(*dir_ / "resumed3");
    third.rawlog = *dir_ / "rest.rawlog";
    third.resume = *dir_ / "end.state";
    SlamApp(third).run(std::cerr);
    expectSameOutputs(*dir_ / "full", *dir_ / "resumed3");
}

// A bad state, config or component fails before the output folder exists.
void expectRefused(SlamApp::Args a, const std::string& message)
{
    try
    {
        SlamApp(a).run(std::cerr);
        ADD_FAILURE() << "no error; expected: " << message;
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(a.out_dir)) << "results written after: " << message;
}

void writeFile(const std::string& path, const std::string& bytes)
{
    std::ofstream f(path, std::ios::binary);
    f << bytes;
}

TEST_F(Resume, BadStatesAreClearErrors)
{
    needCut();
    const std::string good = readFile(*dir_ / "cut.state");
    ASSERT_GT(good.size(), 1000u);
    SlamApp::Args a = argsFor(*dir_ / "refused");
    a.resume = *dir_ / "bad.state";

    std::string other = good;
    other[8] = static_cast<char>(hymm::app::kRunStateVersion + 1);
    writeFile(a.resume, other);
    expectRefused(a, "has format version " + std::to_string(hymm::app::kRunStateVersion + 1));

    writeFile(a.resume, good.substr(0, good.size() / 2));
    expectRefused(a, "is truncated");
    writeFile(a.resume, good.substr(0, 12));
    expectRefused(a, "is truncated");

    std::string flipped = good;
    flipped[good.size() - 100] ^= 0x10;
    writeFile(a.resume, flipped);
    expectRefused(a, "is corrupt");

    writeFile(a.resume, "[DenseSlam]\nlandmark_source = bearing_range\n");
    expectRefused(a, "is not a hymm-slam run state");

    a.resume = *dir_ / "missing.state";
    expectRefused(a, "cannot open the run state");
}

// --save-state-every without --save-state has nowhere to write: refused before any entry
// is processed, with or without --resume.
TEST_F(Resume, SaveStateEveryWithoutSaveStateIsRefused)
{
    SlamApp::Args a = argsFor(*dir_ / "refused");
    a.save_state_every = 50;
    expectRefused(a, "--save-state-every needs --save-state");
    a.resume = *dir_ / "cut.state";
    expectRefused(a, "--save-state-every needs --save-state");
}

// The periodic save on its own: a run whose rawlog turns bad after entry kCut + 30 fails
// there (no results), and the state its last periodic save wrote (after entry kCut)
// resumes on the rest of the sample to the uninterrupted run's outputs.
TEST_F(Resume, PeriodicSaveOfAFailedRunResumesToIdenticalOutputs)
{
    needFull();
    const std::string head = *dir_ / "head.rawlog";
    writeEntries(head, 0, kCut + 30, /*bad_tail=*/true);
    SlamApp::Args crashed = argsFor(*dir_ / "crashed");
    crashed.rawlog = head;
    crashed.save_state = *dir_ / "periodic.state";
    crashed.save_state_every = kCut / 2;
    EXPECT_THROW(SlamApp(crashed).run(std::cerr), std::runtime_error);
    // The failed run's folder holds no results (core::OutputFolder).
    EXPECT_TRUE(!fs::exists(crashed.out_dir) || fs::is_empty(crashed.out_dir));
    ASSERT_TRUE(fs::exists(crashed.save_state));

    writeEntries(*dir_ / "after_periodic.rawlog", kCut, kEnd);
    SlamApp::Args resumed = argsFor(*dir_ / "resumed_periodic");
    resumed.rawlog = *dir_ / "after_periodic.rawlog";
    resumed.resume = crashed.save_state;
    SlamApp(resumed).run(std::cerr);
    EXPECT_GE(expectSameOutputs(*dir_ / "full", *dir_ / "resumed_periodic"), 20u);
}

TEST_F(Resume, StateOfAnotherConfigIsRefused)
{
    needCut();
    std::string ini = readFile(kConfig);
    ini.replace(ini.find("samples_per_return = 5"), 22, "samples_per_return = 6");
    writeFile(*dir_ / "other.ini", ini);
    SlamApp::Args a = argsFor(*dir_ / "refused");
    a.config = *dir_ / "other.ini";
    a.resume = *dir_ / "cut.state";
    expectRefused(a, "saved under a different config: the state has '[ParticlesLayer] samples_per_return = 5'");
}

// Scan landmarks (templates, counters, the acceptance test's random generator and the
// templates' first scans of the free-space check, the wide search, the apparent poses)
// and the scan odometry (its keyframe scan and filters, the wheel increment pending for
// the next scan) on the same sample, with the chapter-5 config: landmarks are created and
// observed on both sides of the cut.
TEST_F(Resume, ScanLandmarksResumeToIdenticalOutputs)
{
    mrpt::config::CConfigFileMemory cfg(readFile(kSrc + "/configs/ch5_scanslam.ini"));
    cfg.write("ScanLandmarks", "wide_max_free_conflict", "0.2");
    std::string ini;
    cfg.getContent(ini);
    writeFile(*dir_ / "scan.ini", ini);
    expectCutResumes(*dir_ / "scan.ini", 200, 400, "scan", [](const hymm::denseslam::DenseSlam& slam) {
        ASSERT_EQ(slam.scanSources().size(), 1u);
        const auto* src = dynamic_cast<const hymm::denseslam::ScanLandmarksSource*>(slam.scanSources()[0].get());
        ASSERT_NE(src, nullptr);
        EXPECT_GT(src->map().templates().size(), 0u);
        EXPECT_GT(src->map().stats().updated, 0u);
        EXPECT_EQ(src->map().firstScans().size(), src->map().templates().size());
        ASSERT_NE(slam.scanOdometry(), nullptr);
        EXPECT_GT(slam.scanOdometry()->stats().fused, 0u);
        // The templates' updates are landmark observations that reached the filter.
        for (const auto& w : hymm::app::runWarnings(slam))
            EXPECT_EQ(w.find("no landmark observation reached the filter"), std::string::npos) << w;
    });
}

// High-level landmarks (the chapter-4 HLL config searching every 20 s): the cut falls
// where one HLL is initialised in the filter and another still pending.
TEST_F(Resume, HighLevelLandmarksResumeToIdenticalOutputs)
{
    std::string ini = readFile(kSrc + "/configs/ch4_hll.ini");
    const auto at = ini.find("period_s = 60");
    ASSERT_NE(at, std::string::npos);
    ini.replace(at, 13, "period_s = 20");
    writeFile(*dir_ / "hll.ini", ini);
    expectCutResumes(*dir_ / "hll.ini", 700, 940, "hll", [](const hymm::denseslam::DenseSlam& slam) {
        const auto* hll = slam.highLevelLandmarks();
        ASSERT_NE(hll, nullptr);
        EXPECT_GE(hll->stats().initialised, 1u);
        EXPECT_GT(hll->hlls().size(), hll->stats().initialised);
    });
}

}  // namespace
