#include "hymm/app/SlamApp.h"
#include "hymm/app/motion_outputs.h"
#include "hymm/app/mrpt_outputs.h"
#include "hymm/app/slam_state.h"

#include <hymm/sim/ground_truth_io.h>

#include <hymm/core/config_utils.h>
#include <hymm/core/output_files.h>
#include <hymm/app/slam_config.h>
#include <hymm/io/RawlogReader.h>
#include <hymm/io/ground_truth_io.h>
#include <hymm/app/MapPlot.h>
#include <hymm/app/slam_outputs.h>
#include <vector>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/system/filesystem.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <stdexcept>

namespace hymm::app
{
SlamApp::SlamApp(Args args) : args_(std::move(args)) {}

const DenseSlam& SlamApp::slam() const
{
    if (!slam_) throw std::logic_error("SlamApp::slam() called before run()");
    return *slam_;
}

namespace
{
using Clock = std::chrono::steady_clock;

// The main loop: one rawlog entry at a time, throttled progress; `after` runs after each
// entry with the count read so far and stops the loop by returning false. Returns the
// seconds.
double processRawlog(DenseSlam& slam, io::RawlogReader& reader, bool quiet,
                     std::vector<FrameTiming>& timing, KeyframeRecorder& keyframes, std::ostream& log,
                     const std::function<bool(size_t)>& after)
{
    const auto t0 = Clock::now();
    auto last_report = t0;
    io::RawlogEntry entry;
    while (reader.next(entry))
    {
        const auto e0 = Clock::now();
        const size_t obs_before = slam.stats().observations;
        slam.processEntry(entry);
        keyframes.record(slam, entry);
        const auto now = Clock::now();
        if (entry.frame || entry.observation)
            timing.push_back({reader.entriesRead(), slam.ekf().numLandmarks(),
                              slam.stats().observations - obs_before,
                              std::chrono::duration<double>(now - e0).count()});
        if (!quiet && now - last_report > std::chrono::seconds(2))
        {
            last_report = now;
            log << "[hymm-slam] entry " << reader.entriesRead() << ", landmarks "
                << slam.ekf().numLandmarks() << ", "
                << std::chrono::duration<double>(now - t0).count() << " s\n"
                << std::flush;
        }
        if (!after(reader.entriesRead())) break;
    }
    slam.flushOdometry();  // [ScanOdometry]: the increments after the last frame
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string absolutePath(const std::string& path)
{
    return std::filesystem::weakly_canonical(std::filesystem::absolute(path)).string();
}
}  // namespace

void SlamApp::run(std::ostream& log)
{
    if (args_.config.empty() || args_.rawlog.empty() || args_.out_dir.empty())
        throw std::invalid_argument("hymm-slam needs --config, --rawlog and --out");
    // With or without --resume: the periodic saves have no file to go to.
    if (args_.save_state_every > 0 && args_.save_state.empty())
        throw std::invalid_argument("--save-state-every needs --save-state");

    // Inputs first: a bad config or rawlog must fail before anything is written.
    slam_ = std::make_unique<DenseSlam>(loadSlamConfig(args_.config));
    io::RawlogReader reader(args_.rawlog);
    std::optional<io::GroundTruth> gt;
    if (!args_.gt_path.empty() || !args_.gt_landmarks.empty() || !args_.gt_objects.empty())
        gt = io::loadGroundTruth(args_.gt_path, args_.gt_landmarks);
    std::vector<dense::Polygon> outlines;
    if (!args_.gt_objects.empty()) outlines = loadObjectOutlines(args_.gt_objects);
    // Motion layers (Sec. 6.3) are scored against which objects moved and when.
    const MotionTruth motion_truth = args_.gt_objects.empty()
                                         ? MotionTruth{}
                                         : motionTruthFromRecords(sim::readObjectOutlines(args_.gt_objects));

    // A saved state continues the run (the rawlog's entries it holds are skipped when it
    // is the same rawlog); like the inputs, a bad state fails before anything is written.
    KeyframeRecorder keyframes;
    StateRun st = startState(keyframes, reader);

    // The output folder before any work: a bad --out fails now, and the results of an
    // earlier run in it are removed (core::OutputFolder). Files are written into its
    // staging folder and appear only when every one of them was written.
    core::OutputFolder folder(args_.out_dir);
    folder.prepare();

    std::vector<FrameTiming> timing;
    const double run_s = processRawlog(*slam_, reader, args_.quiet, timing, keyframes, log, [&](size_t read) {
        if (args_.save_state_every > 0 && read % args_.save_state_every == 0) saveState(st, read, keyframes);
        return args_.stop_after == 0 || read < args_.stop_after;
    });
    if (reader.entriesRead() == 0)
        throw std::runtime_error("rawlog '" + args_.rawlog + "' holds no entries");
    // Before the outputs: writing them refreshes the regions (refreshRegions), which the
    // uninterrupted run would not have done at this point.
    if (!args_.save_state.empty()) saveState(st, reader.entriesRead(), keyframes);
    const size_t entries = st.info.entries - st.info.rawlog_entries + reader.entriesRead();
    const auto warnings = runWarnings(*slam_);
    for (const auto& w : warnings) log << "hymm-slam: warning: " << w << "\n";
    if (args_.strict && !warnings.empty())
        throw std::runtime_error("--strict: " + std::to_string(warnings.size()) +
                                 " run warning(s) (above); no results written");
    writeOutputs(folder.staging(), gt ? &*gt : nullptr, outlines, motion_truth, timing, run_s, entries,
                 warnings);
    writeMrptOutputs(*slam_, keyframes, folder.staging());
    folder.commit();
    if (!args_.quiet)
    {
        std::ifstream s(args_.out_dir + "/summary.txt");
        log << s.rdbuf() << "[hymm-slam] results in " << args_.out_dir << "\n";
    }
}

SlamApp::StateRun SlamApp::startState(KeyframeRecorder& keyframes, io::RawlogReader& reader)
{
    StateRun st;
    if (args_.save_state.empty() && args_.resume.empty()) return st;
    st.info.config = configFingerprint(args_.config);
    st.info.rawlog = absolutePath(args_.rawlog);
    if (args_.resume.empty()) return st;
    const RunInfo saved = loadRunState(args_.resume, st.info.config, *slam_, keyframes);
    st.info.entries = saved.entries;
    if (saved.rawlog != st.info.rawlog) return st;  // a further rawlog: from its start
    // The same rawlog: continue after the entries the state holds.
    if (args_.stop_after > 0 && args_.stop_after <= saved.rawlog_entries)
        throw std::invalid_argument("--stop-after " + std::to_string(args_.stop_after) +
                                    ": the state '" + args_.resume + "' is already past that entry (" +
                                    std::to_string(saved.rawlog_entries) + ")");
    st.info.rawlog_entries = saved.rawlog_entries;
    io::RawlogEntry entry;
    while (reader.entriesRead() < saved.rawlog_entries)
        if (!reader.next(entry))
            throw std::runtime_error("--resume: rawlog '" + args_.rawlog + "' has " +
                                     std::to_string(reader.entriesRead()) + " entries; the state '" +
                                     args_.resume + "' was saved after its entry " +
                                     std::to_string(saved.rawlog_entries));
    return st;
}

void SlamApp::saveState(const StateRun& st, size_t read, const KeyframeRecorder& keyframes) const
{
    RunInfo info = st.info;
    info.entries = st.info.entries - st.info.rawlog_entries + read;
    info.rawlog_entries = read;
    saveRunState(args_.save_state, info, *slam_, keyframes);
}

void SlamApp::writeOutputs(const std::string& out, const io::GroundTruth* gt,
                           const std::vector<dense::Polygon>& outlines,
                           const MotionTruth& motion_truth,
                           const std::vector<FrameTiming>& timing, double run_s, size_t entries,
                           const std::vector<std::string>& warnings)
{
    // The global dense map at the final landmark estimates.
    slam_->refreshRegions();
    writeEstimatedPath(*slam_, out + "path.tum");
    writeEstimatedLandmarks(slam_->ekf(), out + "landmarks.csv");
    if (slam_->scanLandmarks()) writeScanLandmarks(*slam_, out + "scan_landmarks.csv");
    if (args_.png) writeMapPng(makeMapPlot(*slam_, gt), out + "map.png");
    writeDenseOutputs(*slam_, out, args_.png);
    writeMotionOutputs(*slam_, out, args_.png);
    writeHllOutputs(*slam_, out, args_.png);
    if (gt)
    {
        auto metrics = computeMetrics(*slam_, *gt, run_s);
        writeDenseMetrics(metrics, *slam_, outlines, trueTrunks(gt->landmarks));
        if (!args_.gt_objects.empty()) writeMotionMetrics(metrics, *slam_, motion_truth);
        metrics.save(out + "metrics.json");
    }
    writeSummary(*slam_, run_s, entries, out + "summary.txt", warnings);
    writeTiming(timing, out + "timing.csv");
}

bool parseSlamArgs(int argc, char** argv, SlamApp::Args& a, std::ostream& out)
{
    TCLAP::CmdLine cmd("hymm-slam: EKF feature SLAM with dense layers (HYMM)", ' ', "0.1");
    TCLAP::ValueArg<std::string> config("c", "config", ".ini configuration file", true, "", "FILE.ini", cmd);
    TCLAP::ValueArg<std::string> rawlog("r", "rawlog", "input MRPT rawlog", true, "", "FILE.rawlog", cmd);
    TCLAP::ValueArg<std::string> outd("o", "out", "output folder", true, "", "DIR", cmd);
    TCLAP::ValueArg<std::string> gtp("", "gt-path",
        "true path: TUM file, or MRPT simul-landmarks *_ground_truth_robot_path.txt", false, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> gtl("", "gt-landmarks",
        "true landmarks: id,x,y CSV, or MRPT simul-landmarks *_ground_truth.txt", false, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> gto("", "gt-objects",
        "true object outlines (simulator's *_gt_objects.txt): outline metrics of the dense maps",
        false, "", "FILE", cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "no progress output", cmd);
    TCLAP::SwitchArg nopng("", "no-png", "do not write map.png and the dense-map images", cmd);
    TCLAP::SwitchArg strict("", "strict",
        "fail (exit 1, no results) on a run warning: no observation used, most not used, no "
        "landmark observation, no odometry, time going backwards", cmd);
    TCLAP::SwitchArg verbose("", "verbose", "errors with MRPT's call-stack backtraces", cmd);
    TCLAP::ValueArg<std::string> save_state("", "save-state",
        "write the run state to FILE after the last entry (continue with --resume)", false, "", "FILE", cmd);
    TCLAP::ValueArg<size_t> every("", "save-state-every",
        "also write the --save-state FILE after every N rawlog entries", false, 0, "N", cmd);
    TCLAP::ValueArg<std::string> resume("", "resume",
        "continue the run saved in FILE: the same rawlog after the entries it holds, another "
        "rawlog from its start (same config)", false, "", "FILE", cmd);
    TCLAP::ValueArg<size_t> stop_after("", "stop-after",
        "stop after the rawlog's entry N (counted from its start) and write the results", false, 0, "N", cmd);
    // MRPT's TCLAP returns false both after --help and after a usage error (which it
    // has already described): tell them apart so a bad command line exits non-zero.
    if (!cmd.parse(argc, argv))
    {
        for (int i = 1; i < argc; ++i)
        {
            const std::string arg = argv[i];
            if (arg == "--help" || arg == "-h" || arg == "--version") return false;
        }
        throw std::invalid_argument("invalid command line (see --help)");
    }
    (void)out;
    a.config = config.getValue();
    a.rawlog = rawlog.getValue();
    a.out_dir = outd.getValue();
    a.gt_path = gtp.getValue();
    a.gt_landmarks = gtl.getValue();
    a.gt_objects = gto.getValue();
    a.quiet = quiet.getValue();
    a.png = !nopng.getValue();
    a.strict = strict.getValue();
    a.verbose = verbose.getValue();
    a.save_state = save_state.getValue();
    a.save_state_every = every.getValue();
    a.resume = resume.getValue();
    a.stop_after = stop_after.getValue();
    return true;
}

}  // namespace hymm::app
