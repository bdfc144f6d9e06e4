/**
 * @file ReflectorExtractor.h
 * @brief Retro-reflective beacons as point landmarks, found from laser intensities.
 *
 * Reflective tape returns a much stronger echo than natural surfaces, so beams whose
 * intensity is at or above `min_intensity` mark a beacon. Consecutive such beams (split
 * at range jumps larger than `range_jump`) form one beacon. Its centre is the mean of
 * the beam end points; for a cylindrical beacon of known radius the mean lies on the
 * visible surface, so the centre is pushed `beacon_radius` farther along the bearing
 * (range to the centre = range to the surface + radius, as for trunks).
 *
 * Requires a scan with intensities (CObservation2DRangeScan::hasIntensity()).
 * Output measurements are in the sensor frame (see scan_features.h).
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <hymm/extract/scan_features.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <string>
#include <vector>

namespace hymm::extract
{
class ReflectorExtractor
{
public:
    /** Ini section [ReflectorExtractor]; unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        int min_intensity = 200;       //!< [sensor units] beams at or above mark a reflector
        double range_jump = 0.3;       //!< [m] range step that splits two reflectors
        int min_points = 1;            //!< [beams] smaller clusters are rejected (>= 1)
        double max_width = 0.5;        //!< [m] wider bright clusters (e.g. a shiny wall) are rejected
        double beacon_radius = 0.0;    //!< [m] radius of cylindrical beacons (0: flat / point)
        double min_range = 0.1;        //!< [m] shorter returns are skipped
        double max_range = 30.0;       //!< [m] returns at/beyond this (or scan maxRange) are skipped
        double std_range = 0.02;       //!< [m] range noise put in the observation
        double std_bearing = 0.25 * 3.14159265358979323846 / 180.0;  //!< [rad] (ini: std_bearing_deg)

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "ReflectorExtractor") const;
    };

    struct Result
    {
        std::vector<ScanFeature> reflectors;  //!< diameter = 2 * beacon_radius
        BeamCounts beams;
        size_t skipped_invalid = 0;  //!< beams.invalid + beams.not_finite + beams.out_of_range
        size_t clusters = 0;         //!< bright clusters found
        size_t rejected_too_few_points = 0;
        size_t rejected_too_wide = 0;
    };

    /** Throws std::invalid_argument on invalid options. */
    explicit ReflectorExtractor(const Options& options);

    const Options& options() const { return options_; }

    /** Throws std::invalid_argument if the scan carries no intensities. */
    Result extract(const mrpt::obs::CObservation2DRangeScan& scan) const;

    mrpt::obs::CObservationBearingRange extractObservation(
        const mrpt::obs::CObservation2DRangeScan& scan) const;

private:
    const Options options_;
};

}  // namespace hymm::extract
