#include "hymm/sim/RawlogWriter.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <stdexcept>

namespace hymm::sim
{
namespace
{
// Best gzip compression: samples are committed to the repository.
constexpr int kCompressionLevel = 9;
}  // namespace

mrpt::obs::CActionCollection makeActions(const SimFrame& frame)
{
    mrpt::obs::CActionRobotMovement2D mov;
    mov.timestamp = frame.stamp;
    mov.estimationMethod = mrpt::obs::CActionRobotMovement2D::emOdometry;
    const mrpt::poses::CPose2D mean(frame.odometry_mean[0], frame.odometry_mean[1],
                                    frame.odometry_mean[2]);
    mov.rawOdometryIncrementReading = mean;
    mov.poseChange = mrpt::poses::CPosePDFGaussian::Create(
        mean, mrpt::math::CMatrixDouble33(frame.odometry_cov));
    mrpt::obs::CActionCollection acts;
    acts.insert(mov);
    return acts;
}

mrpt::obs::CSensoryFrame makeSensoryFrame(const SimFrame& frame)
{
    mrpt::obs::CSensoryFrame sf;
    if (frame.scan) sf.insert(frame.scan);
    if (frame.detections) sf.insert(frame.detections);
    return sf;
}

RawlogWriter::RawlogWriter(const std::string& path) : path_(path)
{
    out_ = std::make_unique<mrpt::io::CFileGZOutputStream>();
    std::string err;
    if (!out_->open(path, kCompressionLevel, err))
        throw std::runtime_error("cannot create rawlog '" + path + "': " + err);
}

RawlogWriter::~RawlogWriter() = default;

void RawlogWriter::write(const SimFrame& frame)
{
    if (!out_) throw std::logic_error("rawlog '" + path_ + "' is already closed");
    auto arch = mrpt::serialization::archiveFrom(*out_);
    try
    {
        arch << makeActions(frame) << makeSensoryFrame(frame);
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error("error writing rawlog '" + path_ + "': " + e.what());
    }
    ++frames_;
}

void RawlogWriter::close()
{
    if (!out_) return;
    out_->close();
    out_.reset();
}

}  // namespace hymm::sim
