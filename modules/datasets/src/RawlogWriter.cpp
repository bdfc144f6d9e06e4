#include "hymm/datasets/RawlogWriter.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <stdexcept>

#include "hymm/datasets/ImportSummary.h"

namespace hymm::datasets
{
RawlogWriter::RawlogWriter(const std::string& path)
    : path_(path), out_(std::make_unique<mrpt::io::CFileGZOutputStream>())
{
    std::string err;
    if (!out_->open(path, 1, err))
        throw std::runtime_error("cannot create rawlog '" + path + "': " + err);
}

RawlogWriter::~RawlogWriter() = default;

void RawlogWriter::writeFrame(const OdometryIntegrator::Increment& odometry,
                              const mrpt::obs::CObservation::Ptr& obs)
{
    if (!out_) throw std::logic_error("RawlogWriter: '" + path_ + "' already closed");
    mrpt::obs::CActionRobotMovement2D act;
    act.timestamp = obs->timestamp;
    act.estimationMethod = mrpt::obs::CActionRobotMovement2D::emOdometry;
    act.rawOdometryIncrementReading = odometry.mean;
    mrpt::math::CMatrixDouble33 cov;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) cov(r, c) = odometry.cov(r, c);
    act.poseChange = mrpt::poses::CPosePDFGaussian::Create(odometry.mean, cov);

    mrpt::obs::CActionCollection acts;
    acts.insert(act);
    mrpt::obs::CSensoryFrame sf;
    sf.insert(obs);
    auto arch = mrpt::serialization::archiveFrom(*out_);
    arch << acts << sf;
    ++frames_;
}

void RawlogWriter::close()
{
    if (!out_) return;
    const bool ok = out_->fileOpenCorrectly();
    out_->close();
    out_.reset();
    if (!ok) throw std::runtime_error("error writing rawlog '" + path_ + "'");
}

void writeOdometryRawlog(const std::string& path, const OdometryIntegrator& odometry,
                         const std::vector<mrpt::obs::CObservation::Ptr>& observations,
                         ImportSummary& summary)
{
    const auto earlier = [](const auto& a, const auto& b) { return a->timestamp < b->timestamp; };
    if (!std::is_sorted(observations.begin(), observations.end(), earlier))
        throw std::invalid_argument("writeOdometryRawlog: observations not sorted by time");

    RawlogWriter writer(path);
    double t_prev = 0;
    for (size_t k = 0; k < observations.size(); ++k)
    {
        const double t = mrpt::Clock::toDouble(observations[k]->timestamp);
        if (k == 0)
        {
            t_prev = odometry.samples().empty() ? t : std::min(t, odometry.samples().front().t);
            summary.first_time_s = t;
        }
        const auto inc = odometry.integrate(t_prev, t);
        summary.odometry_gap_s += inc.uncovered_s;
        writer.writeFrame(inc, observations[k]);
        summary.last_time_s = t;
        t_prev = t;
    }
    writer.close();
    summary.frames += writer.frames();
    summary.observations += writer.frames();
    summary.outputs.push_back(path);
}

}  // namespace hymm::datasets
