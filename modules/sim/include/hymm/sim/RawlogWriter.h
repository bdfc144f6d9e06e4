/**
 * @file RawlogWriter.h
 * @brief Writes simulated frames as an MRPT rawlog in the actions/sensory-frames format
 *        (what RawlogViewer, kf-slam and mrpt::obs::CRawlog::loadFromRawLogFile read):
 *        per frame one CActionCollection then one CSensoryFrame, gzip-compressed.
 *
 * The action is a CActionRobotMovement2D (estimationMethod = emOdometry) whose poseChange
 * is a CPosePDFGaussian with the frame's odometry increment and covariance; it and every
 * observation carry the frame's timestamp.
 */
#pragma once

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <memory>
#include <string>

#include "hymm/sim/Simulator.h"

namespace mrpt::io
{
class CFileGZOutputStream;
}

namespace hymm::sim
{
/** The odometry action of a frame. */
mrpt::obs::CActionCollection makeActions(const SimFrame& frame);

/** The observations of a frame (laser first, then detections). */
mrpt::obs::CSensoryFrame makeSensoryFrame(const SimFrame& frame);

class RawlogWriter
{
public:
    /** Creates (truncates) `path`; throws std::runtime_error naming it on failure. */
    explicit RawlogWriter(const std::string& path);
    ~RawlogWriter();
    RawlogWriter(const RawlogWriter&) = delete;
    RawlogWriter& operator=(const RawlogWriter&) = delete;

    void write(const SimFrame& frame);

    /** Flushes and closes; throws if the file could not be completed. */
    void close();

    size_t frames() const { return frames_; }

private:
    std::string path_;
    std::unique_ptr<mrpt::io::CFileGZOutputStream> out_;
    size_t frames_ = 0;
};

}  // namespace hymm::sim
