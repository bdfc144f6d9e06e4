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
 *
 * Intensities (optional, `intensity = true`): each return reports the true property of
 * the surface it hit (World.h SurfaceProperties: the object's `property`, [World]
 * landmark_property, or the [World] property_field at the point hit) plus Gaussian
 * noise (std_intensity), rounded to the nearest integer because MRPT stores
 * intensities as int32; beams with no return read 0. The noise comes from its own
 * generator, so switching intensities on leaves the ranges unchanged. With intensities
 * off (the default) the scan has none (hasIntensity() is false) and the two keys are
 * not written back, so existing scenarios keep their saved configuration.
 */
#pragma once

#include <hymm/core/OptionTable.h>

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
        bool intensity = false;    //!< report each return's surface property as intensity
        double std_intensity = 0;  //!< intensity noise, 1 sigma [intensity units]

        /** Number of beams: fov / resolution + 1, rounded. */
        size_t beamCount() const;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();

        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                              const std::string& section) const override;
    };

    /** `seed` drives the range and bearing noise, `intensity_seed` the intensity noise. */
    LaserSimulator(const Options& options, uint32_t seed, uint32_t intensity_seed);

    /** A scan from the vehicle at `vehicle_pose` (tracked point, global) of the world as
     *  it is at time `t` [s from the start], stamped `stamp`. */
    mrpt::obs::CObservation2DRangeScan::Ptr observe(const World& world,
                                                    const Eigen::Vector3d& vehicle_pose, double t,
                                                    mrpt::Clock::time_point stamp);

    const Options& options() const { return options_; }

private:
    /** A return's intensity: the surface property plus noise, rounded (MRPT: int32). */
    int32_t intensityOf(double property);

    const Options options_;
    mrpt::random::CRandomGenerator rng_;
    mrpt::random::CRandomGenerator intensity_rng_;
};

}  // namespace hymm::sim
