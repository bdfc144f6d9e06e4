/**
 * @file RawlogWriter.h
 * @brief A converted dataset as an MRPT rawlog: one odometry action + sensory frame per
 *        observation (format: hymm/io/OdometryRawlogWriter.h).
 */
#pragma once

#include <mrpt/obs/CObservation.h>

#include <string>
#include <vector>

#include "hymm/datasets/OdometryIntegrator.h"

namespace hymm::datasets
{
struct ImportSummary;

/** Writes one frame per observation (sorted by time) through
 *  hymm::io::OdometryRawlogWriter, with the odometry integrated since the previous
 *  observation; counts frames, time span and odometry gaps into `summary`. */
void writeOdometryRawlog(const std::string& path, const OdometryIntegrator& odometry,
                         const std::vector<mrpt::obs::CObservation::Ptr>& observations,
                         ImportSummary& summary);

}  // namespace hymm::datasets
