/**
 * @file LandmarkDetector.h
 * @brief A range-bearing landmark detector (the thesis's simulated observation sensor):
 *        the centre of every landmark in range and field of view, with Gaussian noise.
 *
 * The true (range, bearing) comes from the same model the filters use
 * (hymm::core::observeRangeBearing, sensor mounting included). A landmark is reported
 * when min_range_m <= range <= max_range_m, |bearing| <= fov / 2 and, with `occlusion`,
 * no object or other trunk cuts the line of sight before the landmark's own trunk.
 * Readings are range + N(0, std_range_m) and bearing + N(0, std_bearing), wrapped to
 * (-pi, pi]. With known_ids the landmarkID is the true id, otherwise -1 (unknown data
 * association, as for a real detector).
 */
#pragma once

#include <hymm/core/OptionTable.h>

#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/random/RandomGenerators.h>

#include "hymm/sim/SensorOptions.h"
#include "hymm/sim/World.h"

namespace hymm::sim
{
class LandmarkDetector
{
public:
    /** Section [LandmarkDetector]: the common sensor keys plus the ones below. */
    struct Options : public SensorOptions
    {
        Options();
        double min_range_m = 0;  //!< closer landmarks are not reported [m]
        bool known_ids = false;  //!< report the true landmark id (else -1)
        bool occlusion = true;   //!< objects and trunks hide what is behind them

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();

        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                              const std::string& section) const override;
    };

    LandmarkDetector(const Options& options, uint32_t seed);

    /** Detections from the vehicle at `vehicle_pose` at time `t`, stamped `stamp`. */
    mrpt::obs::CObservationBearingRange::Ptr observe(const World& world,
                                                     const Eigen::Vector3d& vehicle_pose, double t,
                                                     mrpt::Clock::time_point stamp);

    const Options& options() const { return options_; }

private:
    const Options options_;
    mrpt::random::CRandomGenerator rng_;
};

}  // namespace hymm::sim
