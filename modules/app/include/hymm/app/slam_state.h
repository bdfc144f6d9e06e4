/**
 * @file slam_state.h
 * @brief hymm-slam's saved run state (--save-state, --save-state-every, --resume): a run
 *        continued from it gives, file for file, the results of the uninterrupted run.
 *
 * File layout (little-endian):
 *   8 bytes  magic "HYMMSTAT"
 *   uint32   format version (kRunStateVersion)
 *   uint64   payload size [bytes]
 *   uint64   FNV-1a 64 checksum of the payload
 *   payload  an MRPT CArchive: RunInfo, DenseSlam::saveState(), KeyframeRecorder
 *            (path index and CSensoryFrame of each keyframe: map.simplemap, run.rawlog).
 * A file without the magic, of another version, shorter than its header says (truncated),
 * with a wrong checksum (corrupt), or saved under another config (RunInfo::config: the
 * .ini's sections, keys and values, comments and order aside) is refused with a message
 * naming the file (hymm-slam then exits before writing anything; a pipeline that failed to
 * load may hold part of the state and is to be discarded).
 * Source: slam_state.cpp.
 */
#pragma once

#include <hymm/app/mrpt_outputs.h>
#include <hymm/denseslam/DenseSlam.h>

#include <cstdint>
#include <string>

namespace hymm::app
{
/** Format version of the state file; a reader accepts this one only. */
constexpr std::uint32_t kRunStateVersion = 13;  // 2: the motion layers; 3: scan landmarks, HLLs; 4: observations_invalid_geometry; 5: point source counts by name, the keyframes' odometry; 6: template augmentation counters; 7: the points layer's bound by area; 8: motion layers of fallback tiles; 9: the scan landmarks' fused viewpoints; 10: auxiliary EKF blocks, the scan landmarks' apparent poses; 11: the scan landmarks' first scans; 12: their revisits; 13: the scan odometry (keyframe scan, filters, the steps' covariance since the keyframe), the pending wheel increment, the turn bias state's counters

/** What hymm-slam keeps beside the pipeline. */
struct RunInfo
{
    std::string config;         //!< configFingerprint() of the run's .ini
    std::string rawlog;         //!< absolute path of the rawlog being processed at the save
    std::uint64_t rawlog_entries = 0;  //!< entries of that rawlog processed (from its start)
    std::uint64_t entries = 0;         //!< entries processed over every rawlog of the run
};

/** The .ini's content as sorted "[section] key = value" lines (comments, blank lines
 *  and order aside). Throws like loadSlamConfig on an unreadable file. */
std::string configFingerprint(const std::string& ini_path);

/** Writes the state to `path` (to a temporary name first, renamed when complete: an
 *  interrupted save leaves the previous state). Throws std::runtime_error when the file
 *  cannot be written. */
void saveRunState(const std::string& path, const RunInfo& info, const denseslam::DenseSlam& slam,
                  const KeyframeRecorder& keyframes);

/** Reads a state into `slam` (built from the same config) and `keyframes`; `config` is
 *  the current .ini's configFingerprint(). Throws std::runtime_error naming `path` on a
 *  missing, foreign, other-version, truncated or corrupt file, or another config. */
RunInfo loadRunState(const std::string& path, const std::string& config, denseslam::DenseSlam& slam,
                     KeyframeRecorder& keyframes);

}  // namespace hymm::app
