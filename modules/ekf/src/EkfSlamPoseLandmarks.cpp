/**
 * @file EkfSlamPoseLandmarks.cpp
 * @brief 3-DOF pose landmarks in the EKF (Scan-SLAM, thesis 5.2.3, 5.3.2, 5.5): exact
 *        augmentation with the frame's global pose, and the update with a
 *        vehicle-relative pose observation, gated by its NIS after the alignment.
 */
#include <mrpt/math/distributions.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>
#include <cmath>

#include "hymm/ekf/EkfSlam.h"
#include "hymm/ekf/pose_landmark_model.h"

namespace hymm::ekf
{
namespace
{
bool validCovariance3(const Eigen::Matrix3d& R)
{
    if (!R.allFinite() || (R - R.transpose()).cwiseAbs().maxCoeff() > 1e-9 * (1 + R.cwiseAbs().maxCoeff()))
        return false;
    Eigen::LLT<Eigen::Matrix3d> llt(R);
    return llt.info() == Eigen::Success;
}

/** The passive blocks see the gain of a pose-landmark update (landmark at offset o)
 *  through their cross-covariance, read before P moves. */
void updatePassive(PassiveStates& passive, const Eigen::Matrix3d& Hv, const Eigen::Matrix3d& Hl,
                   Eigen::Index o, const Eigen::LLT<Eigen::Matrix3d>& llt, const Eigen::MatrixXd& Wt,
                   const Eigen::Vector3d& y)
{
    const Eigen::MatrixXd& Cpa = passive.crossAll();
    const Eigen::MatrixXd PpHt = Cpa.leftCols<3>() * Hv.transpose() + Cpa.middleCols<3>(o) * Hl.transpose();
    const Eigen::MatrixXd Wp = llt.matrixL().solve(PpHt.transpose()).transpose();
    passive.applyUpdate(Wp, Wt.transpose(), y);
}
}  // namespace

long EkfSlam::addPoseLandmark(const Eigen::Vector3d& z, const Eigen::Matrix3d& R,
                              const Eigen::Vector3d& sensor, long id)
{
    if (!z.allFinite() || !validCovariance3(R))
        throw std::invalid_argument("addPoseLandmark: z or R not finite / R not PD");
    Eigen::Matrix3d G_v, G_z;
    const Eigen::Vector3d x_l = poseLandmarkFromObservation(x_.head<3>(), z, sensor, &G_v, &G_z);
    // Eq. 2.53 for a 3-DOF block: P_LL = G_v P_vv G_v^T + G_z R G_z^T.
    return addLandmark(x_l, G_v, G_z * R * G_z.transpose(), id);
}

PoseUpdateReport EkfSlam::updatePoseLandmark(long id, const Eigen::Vector3d& z,
                                             const Eigen::Matrix3d& R,
                                             const Eigen::Vector3d& sensor, double gate_prob)
{
    PoseUpdateReport rep;
    if (!z.allFinite() || !validCovariance3(R))
    {
        rep.outcome = PoseUpdateReport::Outcome::invalid;
        return rep;
    }
    const LandmarkBlock& b = layout_.get(id);
    if (b.dim != 3)
        throw std::invalid_argument("updatePoseLandmark: landmark " + std::to_string(id) +
                                    " is not a 3-DOF pose block");
    const auto o = static_cast<Eigen::Index>(b.offset);
    Eigen::Matrix3d Hv, Hl;
    const Eigen::Vector3d h =
        poseLandmarkObservation(x_.head<3>(), x_.segment<3>(o), sensor, &Hv, &Hl);
    Eigen::Vector3d nu = z - h;
    nu.z() = mrpt::math::wrapToPi(nu.z());
    // P H^T from the vehicle and the landmark columns only (H is zero elsewhere).
    const Eigen::MatrixXd PHt = activeP().leftCols<3>() * Hv.transpose() + activeP().middleCols<3>(o) * Hl.transpose();
    Eigen::Matrix3d S = Hv * PHt.topRows<3>() + Hl * PHt.middleRows<3>(o) + R;
    S = (0.5 * (S + S.transpose())).eval();
    Eigen::LLT<Eigen::Matrix3d> llt(S);
    if (llt.info() != Eigen::Success)
    {
        rep.outcome = PoseUpdateReport::Outcome::numeric;
        return rep;
    }
    const Eigen::Vector3d y = llt.matrixL().solve(nu);
    rep.nis = y.squaredNorm();
    // Thesis 5.5: the aligned observation is verified by a gate before it is used.
    if (gate_prob > 0 && gate_prob < 1 && rep.nis > mrpt::math::chi2inv(gate_prob, 3))
    {
        rep.outcome = PoseUpdateReport::Outcome::gated;
        return rep;
    }
    const Eigen::MatrixXd Wt = llt.matrixL().solve(PHt.transpose());
    if (!Wt.allFinite() || !y.allFinite())
    {
        rep.outcome = PoseUpdateReport::Outcome::numeric;
        return rep;
    }
    if (passive_.numBlocks() > 0) updatePassive(passive_, Hv, Hl, o, llt, Wt, y);
    x_.noalias() += Wt.transpose() * y;
    x_[2] = mrpt::math::wrapToPi(x_[2]);
    x_[o + 2] = mrpt::math::wrapToPi(x_[o + 2]);
    // P -= W W^T (the Joseph form for the optimal gain; see fuse()), kept symmetric.
    activeP().selfadjointView<Eigen::Lower>().rankUpdate(Wt.transpose(), -1.0);
    activeP().triangularView<Eigen::StrictlyUpper>() = activeP().transpose().triangularView<Eigen::StrictlyUpper>();
    ++layout_.get(id).times_seen;
    rep.outcome = PoseUpdateReport::Outcome::updated;
    return rep;
}

}  // namespace hymm::ekf
