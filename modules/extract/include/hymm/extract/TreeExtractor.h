/**
 * @file TreeExtractor.h
 * @brief Tree trunks (and poles) as point landmarks from one 2D laser scan.
 *
 * The landmarks of the thesis' outdoor experiments (Victoria Park, Sec. 2.10; the car
 * park of Sec. 3.10) are trunk centres extracted from laser scans. Steps:
 *  1. Beam validation: beams flagged invalid, NaN/inf, negative, below `min_range` or at
 *     or beyond `max_range` (no return) are skipped and counted.
 *  2. Clustering: consecutive usable beams whose ranges differ by at most `range_jump`
 *     form one object (range discontinuities separate objects).
 *  3. Occlusion: a cluster whose neighbour beam on either side returned a CLOSER range is
 *     partly hidden behind another object; its visible width, and hence its diameter and
 *     centre, would be wrong, so it is rejected (standard practice with the Victoria Park
 *     data). Clusters touching the first or last beam are cut by the field of view and
 *     rejected for the same reason.
 *  4. Circle model: the trunk is a circle. The centre lies behind the visible surface, so
 *     range to the centre = range to the surface + radius (never the surface range itself).
 *     With at least `fit_min_points` beams the circle is fitted by least squares
 *     (circle_fit.h). When the fit is ill-conditioned (too few points, collinear points,
 *     a centre in front of the surface, or a diameter inconsistent with the angular width
 *     of the cluster by more than `max_fit_width_ratio`) the fallback model is used: centre
 *     on the mean bearing of the beams, at (closest range + r), with r from the angular
 *     width w = n * beam spacing: sin(w/2) = r / (closest + r).
 *  5. Acceptance: RMS distance of the points to the circle <= `max_fit_rms` (walls and
 *     irregular objects fail), and `min_diameter` <= diameter <= `max_diameter` (long
 *     straight segments fit huge circles and fail here).
 *
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
class TreeExtractor
{
public:
    /** Ini section [TreeExtractor]; unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        double min_diameter = 0.05;  //!< [m] smallest accepted trunk diameter (> 0)
        double max_diameter = 1.5;   //!< [m] largest accepted trunk diameter
        double range_jump = 0.3;     //!< [m] range step between consecutive beams that splits clusters
        int min_points = 3;          //!< [beams] fewer beams: rejected (>= 1)
        int fit_min_points = 5;      //!< [beams] fewer beams: fallback model instead of a fit (>= 3)
        double min_range = 0.1;      //!< [m] shorter returns are skipped
        double max_range = 30.0;     //!< [m] returns at/beyond this (or the scan's maxRange) are skipped
        double max_fit_rms = 0.05;   //!< [m] largest RMS distance of the points to the circle
        /** Fit accepted only if fitted diameter / angular-width diameter is within
         *  [1/ratio, ratio]; otherwise the fallback model is used (> 1). */
        double max_fit_width_ratio = 2.0;
        bool reject_occluded = true;    //!< reject clusters next to a closer return
        bool reject_scan_edges = true;  //!< reject clusters touching the first/last beam
        double std_range = 0.05;        //!< [m] range noise put in the observation
        double std_bearing = 0.5 * 3.14159265358979323846 / 180.0;  //!< [rad] (ini: std_bearing_deg)

        /** Strict load: unknown keys and out-of-range values throw std::invalid_argument
         *  naming the section, key and value. Absent keys keep their defaults. */
        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        /** Throws std::invalid_argument if a value or combination is invalid. */
        void validate(const std::string& section = "TreeExtractor") const;
    };

    /** Why clusters were rejected (each cluster counted once, first failing reason). */
    struct Rejections
    {
        size_t too_few_points = 0;
        size_t scan_edge = 0;
        size_t occluded = 0;
        size_t bad_fit = 0;  //!< RMS of the points to the circle above max_fit_rms
        size_t too_small = 0;
        size_t too_large = 0;
    };

    struct Result
    {
        std::vector<ScanFeature> trees;
        BeamCounts beams;
        size_t skipped_invalid = 0;  //!< beams.invalid + beams.not_finite + beams.out_of_range
        size_t clusters = 0;
        Rejections rejected;
    };

    /** Throws std::invalid_argument on invalid options (see Options::validate). */
    explicit TreeExtractor(const Options& options);

    const Options& options() const { return options_; }

    /** Extracts trunks from `scan` (measurements in the sensor frame). */
    Result extract(const mrpt::obs::CObservation2DRangeScan& scan) const;

    /** extract() packaged as an MRPT observation (landmarkID = -1, the scan's sensorPose,
     *  noise from the options). */
    mrpt::obs::CObservationBearingRange extractObservation(
        const mrpt::obs::CObservation2DRangeScan& scan) const;

private:
    const Options options_;
};

}  // namespace hymm::extract
