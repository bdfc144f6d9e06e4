#include "hymm/io/OdometryRawlogWriter.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <stdexcept>

namespace hymm::io
{
OdometryRawlogWriter::OdometryRawlogWriter(const std::string& path, int compression_level)
    : path_(path), out_(std::make_unique<mrpt::io::CFileGZOutputStream>())
{
    std::string err;
    if (!out_->open(path, compression_level, err))
        throw std::runtime_error("cannot create rawlog '" + path + "': " + err);
}

OdometryRawlogWriter::~OdometryRawlogWriter() = default;

void OdometryRawlogWriter::writeFrame(mrpt::Clock::time_point stamp,
                                      const mrpt::poses::CPose2D& increment,
                                      const Eigen::Matrix3d& cov,
                                      const std::vector<mrpt::obs::CObservation::Ptr>& observations)
{
    if (!out_) throw std::logic_error("rawlog '" + path_ + "' is already closed");
    mrpt::obs::CActionRobotMovement2D mov;
    mov.timestamp = stamp;
    // MRPT serialises an emOdometry action as the raw increment plus its own motion-model
    // parameters and rebuilds poseChange from that model on reading, which would replace
    // the covariance propagated from the control noise. Any other method stores the PDF
    // as given; emScan2DMatching is the one MRPT readers (getBestMovementEstimation,
    // RawLogViewer, kf-slam) accept as a pose-change estimate.
    mov.estimationMethod = mrpt::obs::CActionRobotMovement2D::emScan2DMatching;
    mov.rawOdometryIncrementReading = increment;
    mov.poseChange = mrpt::poses::CPosePDFGaussian::Create(increment, mrpt::math::CMatrixDouble33(cov));
    mrpt::obs::CActionCollection acts;
    acts.insert(mov);
    mrpt::obs::CSensoryFrame sf;
    for (const auto& o : observations)
        if (o) sf.insert(o);
    try
    {
        auto arch = mrpt::serialization::archiveFrom(*out_);
        arch << acts << sf;
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error("error writing rawlog '" + path_ + "': " + e.what());
    }
    ++frames_;
}

void OdometryRawlogWriter::close()
{
    if (!out_) return;
    const bool ok = out_->fileOpenCorrectly();
    out_->close();
    out_.reset();
    if (!ok) throw std::runtime_error("error writing rawlog '" + path_ + "'");
}

}  // namespace hymm::io
