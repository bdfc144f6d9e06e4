/**
 * @file scan_features.h
 * @brief Landmark measurements extracted from one laser scan, and their conversion to an
 *        MRPT range-bearing observation.
 *
 * All measurements are in the SENSOR frame (the frame of the scan, before applying the
 * scan's sensorPose): range to the landmark centre and bearing of the centre, so that the
 * EKF observation model, which takes the mounting pose from the observation, applies.
 */
#pragma once

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <cstddef>
#include <vector>

namespace hymm::extract
{
/** One extracted landmark (tree trunk, pole, reflector). */
struct ScanFeature
{
    double range = 0;     //!< sensor to landmark centre [m]
    double bearing = 0;   //!< direction of the centre in the sensor frame [rad], (-pi, pi]
    double diameter = 0;  //!< estimated diameter [m] (0 if the extractor does not measure it)
    double fit_rms = 0;   //!< RMS distance of the cluster points to the fitted model [m]
    size_t first_beam = 0;  //!< index of the first beam of the cluster
    size_t last_beam = 0;   //!< index of the last beam of the cluster (inclusive)
    /** True when the centre came from the fallback model (mean bearing, closest range +
     *  radius from the angular width) because the circle fit was ill-conditioned. */
    bool used_fallback = false;
};

/** How the beams of a scan were used; every beam falls in exactly one of the first four. */
struct BeamCounts
{
    size_t total = 0;
    size_t used = 0;          //!< valid beams inside [min_range, max_range]
    size_t invalid = 0;       //!< flagged invalid by the sensor (no return)
    size_t not_finite = 0;    //!< NaN or infinite range values
    size_t out_of_range = 0;  //!< negative, below min_range, or at/beyond max_range
};

/** Noise and metadata copied into the MRPT observation. */
struct BearingRangeNoise
{
    double std_range = 0;    //!< [m]
    double std_bearing = 0;  //!< [rad]
};

/**
 * Builds an mrpt::obs::CObservationBearingRange from extracted features: landmarkID = -1
 * (unidentified), pitch 0, sensorLocationOnRobot = the scan's sensorPose, timestamp and
 * sensorLabel copied, field of view = the scan aperture, maxSensorDistance = the scan's
 * maxRange, and diagonal noise from `noise` (validCovariances = false).
 */
mrpt::obs::CObservationBearingRange toBearingRangeObservation(
    const mrpt::obs::CObservation2DRangeScan& scan, const std::vector<ScanFeature>& features,
    const BearingRangeNoise& noise);

}  // namespace hymm::extract
