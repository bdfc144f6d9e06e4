/**
 * @file OdometryModel.h
 * @brief The Gaussian an odometry reading gives the filter when the rawlog carries no
 *        covariance: observation-format rawlogs (MRPT 2's default) hold
 *        CObservationOdometry, the vehicle's accumulated odometry pose, and DenseSlam
 *        predicts with the increment between two readings.
 *
 * Models ([DenseSlam] odometry_model):
 *  - `thrun` (default): MRPT's CActionRobotMovement2D odometry model of Thrun, Burgard
 *    and Fox (Probabilistic Robotics, 2006, p. 136) with the TOptions_ThrunModel
 *    parameters (defaults: MRPT's). The increment is split into a rotation rot1 towards
 *    the new position, a translation trans and a second rotation rot2; MRPT draws each
 *    with the standard deviation
 *        s_rot1  = a1 |rot1| + a2 trans,
 *        s_trans = a3 trans + a4 (|rot1| + |rot2|),
 *        s_rot2  = a1 |rot2| + a2 trans,
 *    and adds independent noise of additional_std_xy to x, y and additional_std_phi to
 *    phi. MRPT represents the result by particles; the EKF needs a Gaussian: its mean
 *    is the reading, its covariance the exact covariance of MRPT's samples (moments of
 *    x = trans cos rot1, y = trans sin rot1, phi = rot1 + rot2 with independent normal
 *    rot1, trans, rot2; OdometryModel.cpp), which a first-order linearisation would
 *    underestimate along the track by 11 % at MRPT's defaults. A test compares it
 *    with the sample covariance of MRPT's own particles.
 *    As in MRPT, rot1 = atan2(y, x): a vehicle reversing has |rot1| near pi and gets
 *    the rotation noise of a half turn (set a1 small for such vehicles).
 *  - `gaussian`: MRPT's closed-form Gaussian model (CActionRobotMovement2D::
 *    computeFromOdometry with mmGaussian and MRPT's TOptions_GaussianModel defaults),
 *    the covariance MRPT gives an emOdometry action read from a rawlog.
 *  - `none`: a zero covariance (only odometry_std_* and the filter's stabilising noise).
 * odometry_cov_scale and odometry_std_* apply on top of every model, as for actions.
 */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPosePDFGaussian.h>

namespace hymm::denseslam
{
enum class OdometryModel
{
    Thrun,
    Gaussian,
    None
};

/** MRPT's CActionRobotMovement2D::TMotionModelOptions::TOptions_ThrunModel parameters
 *  (defaults read from MRPT's struct). */
struct ThrunOdometryParams
{
    double alpha1_rot_rot;      //!< [rad/rad]
    double alpha2_rot_trans;    //!< [rad/m]
    double alpha3_trans_trans;  //!< [m/m]
    double alpha4_trans_rot;    //!< [m/rad]
    double additional_std_xy;   //!< [m]
    double additional_std_phi;  //!< [rad]
    ThrunOdometryParams();
};

/** The increment `inc` with the covariance of `model` (see the file comment). */
mrpt::poses::CPosePDFGaussian odometryIncrementPdf(const mrpt::poses::CPose2D& inc,
                                                   OdometryModel model,
                                                   const ThrunOdometryParams& thrun);
}  // namespace hymm::denseslam
