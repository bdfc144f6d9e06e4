/**
 * @file RawlogWriter.h
 * @brief Writes MRPT rawlogs in the actions/sensory-frames format (what RawlogViewer
 *        and mrpt::obs::CRawlog read): CActionCollection, CSensoryFrame, alternating,
 *        serialized into a gz-compressed stream.
 */
#pragma once

#include <mrpt/obs/CObservation.h>

#include <memory>
#include <string>
#include <vector>

#include "hymm/datasets/OdometryIntegrator.h"

namespace mrpt::io
{
class CFileGZOutputStream;
}

namespace hymm::datasets
{
struct ImportSummary;

class RawlogWriter
{
   public:
    /** Creates (truncates) `path`; throws std::runtime_error naming it on failure. */
    explicit RawlogWriter(const std::string& path);
    ~RawlogWriter();
    RawlogWriter(const RawlogWriter&) = delete;
    RawlogWriter& operator=(const RawlogWriter&) = delete;

    /** Appends one frame: a CActionRobotMovement2D (odometry estimate, poseChange a
     *  CPosePDFGaussian) stamped like `obs`, then a sensory frame holding `obs`. */
    void writeFrame(const OdometryIntegrator::Increment& odometry,
                    const mrpt::obs::CObservation::Ptr& obs);

    size_t frames() const { return frames_; }

    /** Flushes and closes; throws if the stream reported an error. */
    void close();

   private:
    std::string path_;
    std::unique_ptr<mrpt::io::CFileGZOutputStream> out_;
    size_t frames_ = 0;
};

/**
 * Writes one frame per observation (sorted by timestamp; throws otherwise). The
 * odometry of frame k integrates the controls from frame k-1 to frame k; frame 0 starts
 * at the earlier of the first control and the first observation, which is therefore the
 * origin of the rawlog's odometry. Updates frames/observations/time span/odometry gaps of
 * `summary` and adds `path` to its outputs.
 */
void writeOdometryRawlog(const std::string& path, const OdometryIntegrator& odometry,
                         const std::vector<mrpt::obs::CObservation::Ptr>& observations,
                         ImportSummary& summary);

}  // namespace hymm::datasets
