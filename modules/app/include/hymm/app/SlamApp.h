/**
 * @file SlamApp.h
 * @brief Everything `hymm-slam` does, as a library class: read the .ini and the
 *        rawlog, run DenseSlam over every entry, write the outputs, and evaluate
 *        against ground truth when it is given (the counterpart of MRPT's KFSLAMApp).
 *
 * Outputs in `out_dir`:
 *  - path.tum        estimated vehicle path (TUM format, rawlog timestamps)
 *  - landmarks.csv   id,x,y,cxx,cxy,cyy (final estimates and 2x2 covariances)
 *  - map.png         path and landmarks with 3-sigma ellipses (over the truth if known)
 *  - metrics.json    with ground truth: path RMSE, landmark errors, NEES statistics
 *  - summary.txt     counters (associations, rejections, skipped readings) and timing
 *  - timing.csv      processing time of every sensory frame against map size
 *  - map.3Dscene     for SceneViewer3D, map.simplemap (keyframes for MRPT's apps) and,
 *    with dense layers, map.hymm (the hybrid map as dense::CHybridMetricMap): see
 *    mrpt_outputs.h
 *  - scan_landmarks.csv  with landmark_source scan_landmarks: id,x,y,phi, the 3x3
 *                    covariance and the template's point count (writeScanLandmarks);
 *                    map.png then also shows templates, frame axes and 3-sigma ellipses
 * and with dense layers / the classic grid on ([DenseSlam] dense_layers, classic_grid):
 *  - regions.txt, points.{png,bin,txt}, occupancy.{png,gridmap}, occupancy_regions.csv,
 *    particles.{png,bin,txt}, sog.bin, sog_surface.png, sog_ellipses.png,
 *    property{,_std}.gridmap, property_{mean,std}.png, classic_grid.{png,gridmap}: each
 *    enabled layer's files (see writeDenseOutputs);
 *  - metrics.json gains "dense": counts and memory per layer, and with --gt-objects the
 *    outline accuracy and coverage of every dense map against the true object outlines;
 *  - summary.txt gains one line per enabled layer.
 *  - .hymm-outputs  the names of the files above that this run wrote (core::OutputFolder:
 *                   the next run into the folder removes them first)
 */
#pragma once

#include <hymm/app/motion_outputs.h>
#include <hymm/app/slam_outputs.h>
#include <hymm/app/slam_state.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/io/ground_truth_io.h>

#include <iosfwd>
#include <string>

namespace hymm::app
{
using denseslam::DenseSlam;

class SlamApp
{
public:
    struct Args
    {
        std::string config;          //!< .ini file (required)
        std::string rawlog;          //!< input rawlog (required)
        std::string out_dir;         //!< output folder, created if missing (required)
        std::string gt_path;         //!< true path: TUM, or MRPT's *_ground_truth_robot_path.txt
        std::string gt_landmarks;    //!< true landmarks: id,x,y CSV, or MRPT's *_ground_truth.txt
        std::string gt_objects;      //!< true object outlines (simulator's *_gt_objects.txt)
        bool quiet = false;          //!< no progress lines
        bool png = true;             //!< write map.png
        bool strict = false;         //!< a run warning (runWarnings) is an error
        bool verbose = false;        //!< errors with MRPT's backtraces (the app prints them)
        /** Run state written after the last entry (slam_state.h); empty: none. */
        std::string save_state;
        size_t save_state_every = 0;  //!< also after every N rawlog entries (0: never)
        /** Run state to continue from: the same rawlog after the entries the state holds,
         *  another rawlog from its start. The config must be the state's. */
        std::string resume;
        size_t stop_after = 0;  //!< stop after the rawlog's entry N (from its start; 0: all)
    };

    explicit SlamApp(Args args);

    /** Runs the whole job. Throws std::exception with a clear message on bad input;
     *  nothing is written to out_dir before the config and rawlog have been opened.
     *  out_dir is then checked and made (core::OutputFolder: an earlier run's results
     *  in it are removed) before the rawlog is processed; all files are written under
     *  temporary names and appear only when every one was written, so a failed run
     *  leaves no results. Run warnings (runWarnings) go to `log` and summary.txt; with
     *  Args::strict they are an error (no results written). */
    void run(std::ostream& log);

    const DenseSlam& slam() const;

private:
    /** Everything after the rawlog: files, figures, metrics, summary, timing. */
    void writeOutputs(const std::string& out, const io::GroundTruth* gt,
                      const std::vector<dense::Polygon>& outlines, const MotionTruth& motion_truth,
                      const std::vector<FrameTiming>& timing, double run_s, size_t entries,
                      const std::vector<std::string>& warnings);

    /** The run's state bookkeeping: config fingerprint, rawlog, entries before this
     *  rawlog's first entry read. */
    struct StateRun
    {
        RunInfo info;
    };
    /** Checks the state options, loads --resume into the pipeline and `keyframes`, and
     *  skips the entries it holds when the rawlog is the state's (slam_state.h). */
    StateRun startState(KeyframeRecorder& keyframes, io::RawlogReader& reader);
    /** Writes --save-state after `read` entries of the current rawlog. */
    void saveState(const StateRun& st, size_t read, const KeyframeRecorder& keyframes) const;

    Args args_;
    std::unique_ptr<DenseSlam> slam_;
};

/** Parses argv for hymm-slam; throws std::invalid_argument on bad usage.
 *  Returns false when --help was asked for (usage already printed). */
bool parseSlamArgs(int argc, char** argv, SlamApp::Args& args, std::ostream& out);

}  // namespace hymm::app
