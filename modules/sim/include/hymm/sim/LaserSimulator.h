/**
 * @file LaserSimulator.h
 * @brief A 2D scanning laser: beams ray-cast exactly against the landmarks' trunks and
 *        the objects' outlines present at the time of the scan.
 *
 * Beams sweep the field of view right to left (MRPT's rightToLeft), spaced by the
 * resolution. A beam with a hit closer than max_range_m reads the true distance plus
 * Gaussian noise (std_range_m, clamped to [0, max_range_m]); a beam with no return is
 * marked invalid (setScanRangeValidity) and reads max_range_m. Bearing noise
 * (std_bearing_deg, default 0) jitters the direction in which each beam is cast while
 * the scan reports the nominal angle.
 */
#pragma once

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/random/RandomGenerators.h>

#include "hymm/sim/SensorOptions.h"
#include "hymm/sim/World.h"

namespace hymm::sim
{
class LaserSimulator
{
public:
    /** Section [LaserSimulator]: the common sensor keys plus resolution_deg. */
    struct Options : public SensorOptions
    {
        Options();
        double resolution = 0.5 * M_PI / 180;  //!< angle between beams [rad] (ini: _deg)

        /** Number of beams: fov / resolution + 1, rounded. */
        size_t beamCount() const;

        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                              const std::string& section) const override;
    };

    LaserSimulator(const Options& options, uint32_t seed);

    /** A scan from the vehicle at `vehicle_pose` (tracked point, global) of the world as
     *  it is at time `t` [s from the start], stamped `stamp`. */
    mrpt::obs::CObservation2DRangeScan::Ptr observe(const World& world,
                                                    const Eigen::Vector3d& vehicle_pose, double t,
                                                    mrpt::Clock::time_point stamp);

    const Options& options() const { return options_; }

private:
    const Options options_;
    mrpt::random::CRandomGenerator rng_;
};

}  // namespace hymm::sim
