/**
 * @file Scenario.h
 * @brief Everything that defines one simulated run, loaded from one MRPT-style .ini.
 *
 * Sections (each optional unless noted; unknown sections or keys are errors):
 *   [Scenario]          name, seed, dt_s, duration_s, laps, start_time_s (below)
 *   [Vehicle]           UTE geometry, speed, control noise (Vehicle.h)
 *   [PathFollower]      the loop driven (required: waypoints) (PathFollower.h)
 *   [World]             landmark and object generation (World.h)
 *   [Object_<name>]     one polygonal object each (World.h)
 *   [LaserSimulator]    2D laser (LaserSimulator.h)
 *   [LandmarkDetector]  range-bearing landmark detector (LandmarkDetector.h)
 *   [WorldPlot]         the optional PNG (WorldPlot.h)
 * Angles are in degrees in the file (keys ending in _deg) and radians in the structs.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <mrpt/config/CLoadableOptions.h>

#include <string>

#include "hymm/sim/LandmarkDetector.h"
#include "hymm/sim/LaserSimulator.h"
#include "hymm/sim/PathFollower.h"
#include "hymm/sim/Vehicle.h"
#include "hymm/sim/World.h"
#include "hymm/sim/WorldPlot.h"

namespace hymm::sim
{
struct Scenario
{
    /** Section [Scenario]. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        std::string name = "scenario";  //!< base name of the output files ([A-Za-z0-9_.-])
        long seed = 1;                  //!< noise seed (the world has its own: World::Options)
        double dt_s = 0.025;            //!< dead-reckoning step (thesis: 0.025 s) [s]
        double duration_s = 0;          //!< run length [s]; 0: drive `laps` laps
        long laps = 1;                  //!< laps of the loop when duration_s = 0
        /** Timestamp of the first frame [s since 1970]. The default, 1970-01-02 00:00 UTC,
         *  is non-zero (MRPT tools take 0 for "no time") and small enough for the 12
         *  significant digits of the TUM files to keep sub-microsecond steps. */
        double start_time_s = 86400;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();

        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                              const std::string& section) const override;
    };

    Options run;
    Vehicle::Options vehicle;
    PathFollower::Options path;
    World::Options world;
    LaserSimulator::Options laser;
    LandmarkDetector::Options detector;
    WorldPlot::Options plot;

    /** Reads every section, strictly, and checks the combination (sensor periods are
     *  multiples of dt_s, at least one sensor is enabled, a loop to drive for laps...).
     *  Throws std::invalid_argument naming section, key and value. */
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg);
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg) const;

    /** The effective configuration as .ini text (reloads to the same scenario). */
    std::string toIniText() const;

    /** Loads `path`; throws if it is missing or invalid (the message names the file). */
    static Scenario fromFile(const std::string& path);

    /** Steps of dt_s between two readings of a sensor with this period. */
    long stepsPerPeriod(double period_s) const;
};

}  // namespace hymm::sim
