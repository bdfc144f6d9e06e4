/**
 * @file run_scenario.h
 * @brief Runs a scenario end to end and writes its files: what hymm-simul does.
 *
 * In `out_dir` (created if missing), with <name> from [Scenario] name:
 *   <name>.rawlog             MRPT rawlog, actions + sensory frames (hymm/io/OdometryRawlogWriter.h)
 *   <name>_gt_path.tum        true pose of the tracked point at every frame (TUM)
 *   <name>_dr_path.tum        dead reckoning from the true start pose, same stamps (TUM)
 *   <name>_gt_landmarks.csv   id,x,y,radius
 *   <name>_gt_objects.txt     true object outlines over time (ground_truth_io.h)
 *   <name>_config.ini         the effective configuration (reloads to the same run)
 *   <name>_gt_properties.txt  with [LaserSimulator] intensity = true: the true surface
 *                             properties the intensities report (ground_truth_io.h)
 *   <name>.png                with `png`: world, true path, laser returns (WorldPlot.h)
 */
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "hymm/sim/Scenario.h"

namespace hymm::sim
{
struct RunSummary
{
    std::string name;
    size_t frames = 0;
    size_t scans = 0;
    size_t detections = 0;  //!< landmark readings in all frames
    size_t landmarks = 0;
    size_t objects = 0;
    double duration_s = 0;     //!< time of the last frame [s]
    double path_length_m = 0;  //!< driven by the tracked point [m]
    std::vector<std::string> files;

    std::string toString() const;
};

/** Runs `scenario` and writes its files into `out_dir`. */
RunSummary runScenario(const Scenario& scenario, const std::string& out_dir, bool png);

/** Loads `config_path`, optionally overrides the noise seed, runs it. */
RunSummary runScenarioFile(const std::string& config_path, const std::string& out_dir,
                           std::optional<long> seed, bool png);

}  // namespace hymm::sim
