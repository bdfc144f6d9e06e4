/**
 * @file DenseSlamOdometry.cpp
 * @brief The pipeline's step 1 (DenseSlam.h): odometry increments checked and predicted,
 *        held for the next scan with [ScanOdometry], and the wheels' turn bias as a state
 *        ([DenseSlam] turn_bias_state) with the vehicle's copy at the reference scan.
 */
#include "hymm/denseslam/DenseSlam.h"
#include "usable_covariance.h"

#include <hymm/core/TimeLogger.h>
#include <hymm/core/turn_bias.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>
#include <cmath>

namespace hymm::denseslam
{
void DenseSlam::processOdometry(const mrpt::poses::CPosePDFGaussian& increment)
{
    // A NaN / inf increment (or covariance) would poison the whole state, and a finite but
    // absurd one (a corrupt reading: no vehicle moves 1 km between two odometry readings)
    // would put the pose where no grid index can represent it: both skipped.
    // The same for a covariance that is no covariance (a negative variance, not symmetric)
    // or claims more than 1 km / a full turn of spread: it would make the filter's
    // covariance indefinite or overflow it.
    constexpr double kMaxStep = 1000.0;  // [m]
    if (!std::isfinite(increment.mean.x()) || !std::isfinite(increment.mean.y()) ||
        !std::isfinite(increment.mean.phi()) || !increment.cov.asEigen().allFinite() ||
        std::hypot(increment.mean.x(), increment.mean.y()) > kMaxStep ||
        !usableCovariance<3>(increment.cov.asEigen(), Eigen::Vector3d(kMaxStep, kMaxStep, 2 * M_PI)))
    {
        ++stats_.odometry_invalid;
        return;
    }
    scanslam::ScanOdometry::Increment inc;
    inc.mean = Eigen::Vector3d(increment.mean.x(), increment.mean.y(), increment.mean.phi());
    inc.cov = increment.cov.asEigen() * options_.odometry_cov_scale;
    inc.cov(0, 0) += options_.odometry_std_xy * options_.odometry_std_xy;
    inc.cov(1, 1) += options_.odometry_std_xy * options_.odometry_std_xy;
    inc.cov(2, 2) += options_.odometry_std_phi * options_.odometry_std_phi;
    ++stats_.predictions;
    if (scan_odometry_)
        // Applied with the next frame's scan (applyPendingOdometry).
        pending_odometry_ = pending_odometry_ ? scanslam::composeIncrements(*pending_odometry_, inc) : inc;
    else
        predict(inc);
}

void DenseSlam::predict(const scanslam::ScanOdometry::Increment& increment)
{
    core::TimedSection tle(profiler_, "denseslam.1_predict");
    const mrpt::poses::CPosePDFGaussian inc(
        mrpt::poses::CPose2D(increment.mean.x(), increment.mean.y(), increment.mean.z()),
        mrpt::math::CMatrixDouble33(increment.cov));
    if (options_.turn_bias_state)
        ekf_.predictOdometryWithTurnBias(inc, kTurnBiasId, options_.turn_bias_walk * options_.turn_bias_walk);
    else
        ekf_.predictOdometry(inc);
}

void DenseSlam::flushOdometry()
{
    if (!pending_odometry_) return;
    predict(*pending_odometry_);
    pending_odometry_.reset();
    if (scan_odometry_) scan_odometry_->reset();
    if (ekf_.layout().has(kReferenceCopyId)) ekf_.removeLandmark(kReferenceCopyId);  // no reference now
}

void DenseSlam::applyPendingOdometry(const mrpt::obs::CSensoryFrame& frame)
{
    if (!scan_odometry_) return;
    const mrpt::obs::CObservation2DRangeScan* scan = nullptr;
    bool reads_pose = false;
    for (const auto& o : frame)
    {
        if (!o) continue;
        // Odometry read inside the frame belongs before the frame's other readings
        // (processObservation skips it then).
        if (IS_CLASS(*o, mrpt::obs::CObservationOdometry)) processOdometryObservation(*o);
        if (!scan) scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(o.get());
        reads_pose = reads_pose || dynamic_cast<const mrpt::obs::CObservationBearingRange*>(o.get()) != nullptr;
    }
    if (!scan)
    {
        // Bearing-range readings need the motion now; the next scan then has no reference
        // where that motion started. Frames of readings the pipeline does not place (IMU,
        // GPS, ...) leave the odometry pending for the next scan.
        if (reads_pose) flushOdometry();
        return;
    }
    core::TimedSection tle(profiler_, "denseslam.1_scan_odometry");
    // No odometry since the last frame: the scan is the next one's reference (the motion
    // in between is unknown, nothing to fuse it with).
    scanslam::ScanOdometry::Increment wheel;
    if (pending_odometry_)
        wheel = *pending_odometry_;
    else
    {
        scan_odometry_->reset();
        wheel.cov = Eigen::Matrix3d::Identity();
    }
    if (options_.turn_bias_state)
    {
        // The bias is a state: the wheels predict through it, and the alignment is an
        // observation of the vehicle relative to its copy at the reference scan, so the
        // heading the wheels miss informs the bias (not only this step).
        if (pending_odometry_) predict(*pending_odometry_);
        else if (ekf_.layout().has(kReferenceCopyId)) ekf_.removeLandmark(kReferenceCopyId);
        scan_odometry_->refine(*scan, unbiasedByState(wheel));
        observeFromReferenceCopy();
        pending_odometry_.reset();
        return;
    }
    const auto inc = scan_odometry_->refine(*scan, wheel);
    tle.stop();
    if (pending_odometry_) predict(inc);
    pending_odometry_.reset();
}

void DenseSlam::processOdometryObservation(const mrpt::obs::CObservation& obs)
{
    const auto& odo = dynamic_cast<const mrpt::obs::CObservationOdometry&>(obs);
    if (!std::isfinite(odo.odometry.x()) || !std::isfinite(odo.odometry.y()) ||
        !std::isfinite(odo.odometry.phi()))
    {
        ++stats_.odometry_invalid;  // the next good reading continues from the last good one
        return;
    }
    if (last_odometry_)
    {
        // The reading carries no covariance: the increment gets the motion model's.
        processOdometry(odometryIncrementPdf(odo.odometry - *last_odometry_,
                                             options_.odometry_model, options_.thrun));
    }
    last_odometry_ = odo.odometry;
}

std::optional<std::pair<double, double>> DenseSlam::turnBias() const
{
    if (!options_.turn_bias_state) return std::nullopt;
    const auto o = static_cast<Eigen::Index>(ekf_.layout().get(kTurnBiasId).offset);
    return std::make_pair(ekf_.mean()[o], std::sqrt(std::max(ekf_.cov()(o, o), 0.0)));
}

scanslam::ScanOdometry::Increment DenseSlam::unbiasedByState(const scanslam::ScanOdometry::Increment& wheel) const
{
    const auto b = turnBias();
    if (!b || !wheel.mean.allFinite()) return wheel;
    Eigen::Vector3d Jb;
    Eigen::Matrix3d Jd;
    scanslam::ScanOdometry::Increment out;
    out.mean = core::turnBiasedIncrement(wheel.mean, b->first, &Jb, &Jd);
    out.cov = Jd * wheel.cov * Jd.transpose() + b->second * b->second * Jb * Jb.transpose();
    out.cov = (0.5 * (out.cov + out.cov.transpose())).eval();
    return out;
}

void DenseSlam::observeFromReferenceCopy()
{
    const auto& m = scan_odometry_->lastRelativeMeasurement();
    if (m && ekf_.layout().has(kReferenceCopyId))
    {
        const auto rep =
            ekf_.updateVehicleFromCopy(kReferenceCopyId, m->mean, m->cov, scan_odometry_->options().gate_prob);
        if (rep.outcome == ekf::PoseUpdateReport::Outcome::updated)
            ++turn_bias_stats_.fused;
        else if (rep.outcome == ekf::PoseUpdateReport::Outcome::gated)
            ++turn_bias_stats_.gated;
        else
            ++turn_bias_stats_.failed;
    }
    if (!scan_odometry_->lastScanIsReference()) return;
    if (ekf_.layout().has(kReferenceCopyId))
        ekf_.recopyVehicle(kReferenceCopyId);
    else
        ekf_.addVehicleCopy(kReferenceCopyId);
    ++turn_bias_stats_.copies;
}

}  // namespace hymm::denseslam
