/**
 * @file ImportSummary.h
 * @brief What a dataset conversion produced and what it skipped, by reason.
 *
 * Real logs have quirks (GPS jumps, no-return ranges, duplicated timestamps, NaN).
 * Converters never stop on them: they skip the item and count it here, so the user
 * can judge the conversion from one printed summary.
 */
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace hymm::datasets
{
struct ImportSummary
{
    std::string format;               //!< "victoria", "carpark", "mrclam"
    size_t frames = 0;                //!< action + sensory-frame pairs written
    size_t observations = 0;          //!< observations written (one per frame here)
    size_t measurements = 0;          //!< landmark detections / valid range beams written
    size_t odometry_samples = 0;      //!< control samples accepted
    size_t ground_truth_poses = 0;    //!< poses written to the ground-truth file
    size_t landmarks = 0;             //!< landmarks written to the landmarks file
    double odometry_gap_s = 0;        //!< frame time not covered by any control sample
    double first_time_s = 0;          //!< first frame timestamp [s, rawlog time base]
    double last_time_s = 0;           //!< last frame timestamp [s, rawlog time base]
    std::map<std::string, size_t> skipped;  //!< reason -> count
    std::map<std::string, size_t> repaired;  //!< items kept after a fix, reason -> count
    std::vector<std::string> outputs;       //!< files written

    void skip(const std::string& reason, size_t n = 1) { skipped[reason] += n; }
    size_t skippedCount(const std::string& reason) const;
    size_t repairedCount(const std::string& reason) const;

    /** Multi-line human-readable report. */
    std::string toString() const;
};

}  // namespace hymm::datasets
