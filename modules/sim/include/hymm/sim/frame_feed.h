/**
 * @file frame_feed.h
 * @brief A SimFrame as a rawlog would carry it: the odometry increment as a Gaussian pose
 *        PDF (the action) and the frame's observations as a sensory frame, in the order a
 *        pipeline takes them.
 */
#pragma once

#include "hymm/sim/Simulator.h"

#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>

namespace hymm::sim
{
/** The odometry increment since the previous frame with its covariance. */
inline mrpt::poses::CPosePDFGaussian odometryIncrement(const SimFrame& f)
{
    return mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(f.odometry_mean[0], f.odometry_mean[1], f.odometry_mean[2]),
                                         mrpt::math::CMatrixDouble33(f.odometry_cov));
}

/** The laser scan (if due), then the landmark detections (if due). */
inline mrpt::obs::CSensoryFrame sensoryFrame(const SimFrame& f)
{
    mrpt::obs::CSensoryFrame sf;
    if (f.scan) sf.insert(f.scan);
    if (f.detections) sf.insert(f.detections);
    return sf;
}

}  // namespace hymm::sim
