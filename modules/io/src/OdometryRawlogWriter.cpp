#include "hymm/io/OdometryRawlogWriter.h"

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace hymm::io
{
namespace
{
gzFile asGz(void* p) { return static_cast<gzFile>(p); }
}  // namespace

OdometryRawlogWriter::OdometryRawlogWriter(const std::string& path, int compression_level)
    : path_(path), tmp_path_(path + ".tmp-" + std::to_string(::getpid()))
{
    // The mode CFileGZOutputStream uses ("wb<level>"): the same bytes as MRPT's writer.
    const std::string mode = "wb" + std::to_string(compression_level);
    errno = 0;
    gz_ = gzopen(tmp_path_.c_str(), mode.c_str());
    if (!gz_)
        throw std::runtime_error("cannot create rawlog '" + path + "': " +
                                 (errno ? std::strerror(errno) : "zlib error"));
}

OdometryRawlogWriter::~OdometryRawlogWriter()
{
    if (gz_)
    {
        gzclose(asGz(gz_));
        std::remove(tmp_path_.c_str());
    }
}

void OdometryRawlogWriter::fail(const std::string& why)
{
    if (gz_) gzclose(asGz(gz_));
    gz_ = nullptr;
    std::remove(tmp_path_.c_str());
    throw std::runtime_error("error writing rawlog '" + path_ + "': " + why);
}

void OdometryRawlogWriter::writeFrame(mrpt::Clock::time_point stamp,
                                      const mrpt::poses::CPose2D& increment,
                                      const Eigen::Matrix3d& cov,
                                      const std::vector<mrpt::obs::CObservation::Ptr>& observations)
{
    if (!gz_) throw std::logic_error("rawlog '" + path_ + "' is already closed");
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
    mrpt::io::CMemoryStream mem;
    try
    {
        auto arch = mrpt::serialization::archiveFrom(mem);
        arch << acts << sf;
    }
    catch (const std::exception& e)
    {
        fail(e.what());
    }
    const auto n = static_cast<unsigned>(mem.getTotalBytesCount());
    if (n > 0 && gzwrite(asGz(gz_), mem.getRawBufferData(), n) != static_cast<int>(n))
    {
        int code = Z_OK;
        const std::string msg = gzerror(asGz(gz_), &code);
        fail(code == Z_ERRNO ? std::strerror(errno) : msg);
    }
    ++frames_;
}

void OdometryRawlogWriter::close()
{
    if (!gz_) return;
    errno = 0;
    const int rc = gzclose(asGz(gz_));
    gz_ = nullptr;
    if (rc != Z_OK)
    {
        const int err = errno;
        std::remove(tmp_path_.c_str());
        throw std::runtime_error("error writing rawlog '" + path_ + "': " +
                                 (rc == Z_ERRNO && err ? std::strerror(err)
                                                       : "zlib error " + std::to_string(rc)));
    }
    if (std::rename(tmp_path_.c_str(), path_.c_str()) != 0)
    {
        const int err = errno;
        std::remove(tmp_path_.c_str());
        throw std::runtime_error("cannot rename '" + tmp_path_ + "' to '" + path_ +
                                 "': " + std::strerror(err));
    }
}

}  // namespace hymm::io
