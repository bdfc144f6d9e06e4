/**
 * @file laser_noise.h
 * @brief Ini section [Laser]: the laser scanner's raw-return noise, one place for every
 *        part that models a return (the delayed store's covariances, the particle and SOG
 *        layers' sensor model, the Scan-SLAM and high-level-landmark templates).
 *
 * The extractors' std_range / std_bearing_deg are the noise of an extracted feature (a
 * trunk centre), not of a return, and stay in their sections. The per-section keys that
 * [Laser] replaces are deprecated: a warning on stderr, and an error when [Laser] sets the
 * same quantity.
 */
#pragma once

#include "hymm/core/OptionTable.h"

#include <mrpt/config/CConfigFileBase.h>

#include <string>

namespace hymm::core
{
struct LaserNoise
{
    double std_range_m = 0.1;      //!< [m]
    double std_bearing_deg = 1.0;  //!< [deg]
    OptionTable table();
};

/**
 * The return noise of `section`, whose own (deprecated) keys are `range_key` [m] and
 * `bearing_deg_key` [deg]: [Laser]'s value where [Laser] sets it (then the section's key
 * is an error), else the section's value as loaded (a warning on stderr when the section
 * sets it). `range_m` and `bearing_rad` hold the section's values on entry.
 */
void applyLaserNoise(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                     const std::string& range_key, const std::string& bearing_deg_key, double& range_m,
                     double& bearing_rad);

}  // namespace hymm::core
