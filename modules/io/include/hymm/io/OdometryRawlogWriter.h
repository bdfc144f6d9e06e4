/**
 * @file OdometryRawlogWriter.h
 * @brief Writes MRPT rawlogs in the actions/sensory-frames format (what RawlogViewer,
 *        MRPT's kf-slam and mrpt::obs::CRawlog read): per frame one CActionCollection
 *        holding a CActionRobotMovement2D (poseChange a CPosePDFGaussian), then one
 *        CSensoryFrame, gzip-compressed. Shared by the simulator and the dataset
 *        converters. The action is marked emScan2DMatching, not emOdometry: MRPT
 *        rebuilds the covariance of an emOdometry action from its default motion model
 *        when reading it, so the covariance written here would be lost.
 *
 *        The rawlog is written as `<path>.tmp-<pid>` and renamed to `path` by close():
 *        a writer destroyed without close() (an importer failing later) removes it, so
 *        no complete-looking rawlog is left behind. Every write and the close are
 *        checked; failures throw naming `path`.
 */
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace hymm::io
{
class OdometryRawlogWriter
{
public:
    /** Starts `path` (under its temporary name) with the given gzip level (1 fast .. 9
     *  small); throws std::runtime_error naming the path on failure. */
    explicit OdometryRawlogWriter(const std::string& path, int compression_level = 1);
    ~OdometryRawlogWriter();
    OdometryRawlogWriter(const OdometryRawlogWriter&) = delete;
    OdometryRawlogWriter& operator=(const OdometryRawlogWriter&) = delete;

    /** Appends one frame: the odometry increment N(`increment`, `cov`) since the previous
     *  frame, stamped `stamp`, then a sensory frame holding `observations` in order (null
     *  pointers are skipped). Throws if the writer is closed or the stream fails. */
    void writeFrame(mrpt::Clock::time_point stamp, const mrpt::poses::CPose2D& increment,
                    const Eigen::Matrix3d& cov,
                    const std::vector<mrpt::obs::CObservation::Ptr>& observations);

    size_t frames() const { return frames_; }

    /** Flushes, closes and renames the file to its final name; throws if any write or
     *  the close failed (the file is then removed). */
    void close();

private:
    void fail(const std::string& why);

    std::string path_;
    std::string tmp_path_;
    void* gz_ = nullptr;  // gzFile
    size_t frames_ = 0;
};

}  // namespace hymm::io
