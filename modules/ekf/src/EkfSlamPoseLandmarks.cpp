/**
 * @file EkfSlamPoseLandmarks.cpp
 * @brief 3-DOF pose landmarks in the EKF (Scan-SLAM, thesis 5.2.3, 5.3.2, 5.5): exact
 *        augmentation with the frame's global pose, and the update with a
 *        vehicle-relative pose observation, gated by its NIS after the alignment.
 */
#include <mrpt/math/distributions.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <optional>

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

/** W_p = P_pa H^T L^-T of the passive rows for one linearisation of a pose-landmark update
 *  (observer at offset ov: 0 the vehicle; landmark at offset o), read before P moves. */
Eigen::MatrixXd passiveGain(const PassiveStates& passive, const Eigen::Matrix3d& Hv, const Eigen::Matrix3d& Hl,
                            Eigen::Index ov, Eigen::Index o, const Eigen::LLT<Eigen::Matrix3d>& llt)
{
    const Eigen::MatrixXd& Cpa = passive.crossAll();
    const Eigen::MatrixXd PpHt = Cpa.middleCols<3>(ov) * Hv.transpose() + Cpa.middleCols<3>(o) * Hl.transpose();
    return llt.matrixL().solve(PpHt.transpose()).transpose();
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

namespace
{
/** One linearisation of a pose-landmark observation at (xv, xl) for the prior (xv0, xl0):
 *  H, P H^T, the Cholesky factor of S and the whitened innovation y = L^-1 nu. */
struct PoseLinearisation
{
    Eigen::Matrix3d Hv, Hl;
    Eigen::MatrixXd PHt;
    Eigen::LLT<Eigen::Matrix3d> llt;
    Eigen::Vector3d y;
};

/** (observer, landmark) linearisation point of EkfSlam::poseFejPoint. */
using FejPoint = std::pair<Eigen::Vector3d, Eigen::Vector3d>;

/** False if S is not positive definite. Iterated EKF (Bell and Cathey 1993): linearised at
 *  x_i the innovation is z - h(x_i) - H_i (x_0 - x_i); at x_i = x_0 the EKF's z - h(x_0). */
bool linearise(const Eigen::Ref<const Eigen::MatrixXd>& P, Eigen::Index ov, Eigen::Index o, const Eigen::Vector3d& z,
               const Eigen::Matrix3d& R, const Eigen::Vector3d& sensor, const Eigen::Vector3d& xv0,
               const Eigen::Vector3d& xl0, const Eigen::Vector3d& xv, const Eigen::Vector3d& xl,
               const FejPoint* fej, SecondOrderTerms second_order, PoseLinearisation& L)
{
    Eigen::Vector3d h = poseLandmarkObservation(xv, xl, sensor, &L.Hv, &L.Hl);
    Eigen::Matrix3d S2 = Eigen::Matrix3d::Zero();
    if (second_order != SecondOrderTerms::Off)
    {
        // EkfSlam::Options::pose_update_second_order, over the joint (observer, landmark)
        // block of P.
        Eigen::Matrix<double, 6, 6> Ps;
        Ps << P.block<3, 3>(ov, ov), P.block<3, 3>(ov, o), P.block<3, 3>(o, ov), P.block<3, 3>(o, o);
        Eigen::Vector3d bias;
        poseObservationSecondOrder(xv, xl, sensor, Ps, bias, S2);
        if (second_order == SecondOrderTerms::Full) h += bias;
    }
    // FEJ-EKF (see LinearisationPoint): the innovation at the estimate, the Jacobians at
    // x_{k|k-1} and at the landmark's first estimate (only with x = x_0, one iteration).
    if (fej) poseLandmarkObservation(fej->first, fej->second, sensor, &L.Hv, &L.Hl);
    Eigen::Vector3d dv = xv0 - xv, dl = xl0 - xl, nu = z - h;
    dv.z() = mrpt::math::wrapToPi(dv.z());
    dl.z() = mrpt::math::wrapToPi(dl.z());
    nu.z() = mrpt::math::wrapToPi(nu.z());
    nu -= L.Hv * dv + L.Hl * dl;
    // P H^T from the observer's and the landmark's columns only (H is zero elsewhere).
    L.PHt = P.middleCols<3>(ov) * L.Hv.transpose() + P.middleCols<3>(o) * L.Hl.transpose();
    Eigen::Matrix3d S = L.Hv * L.PHt.middleRows<3>(ov) + L.Hl * L.PHt.middleRows<3>(o) + R + S2;
    S = (0.5 * (S + S.transpose())).eval();
    L.llt.compute(S);
    if (L.llt.info() != Eigen::Success) return false;
    L.y = L.llt.matrixL().solve(nu);
    return true;
}

/** The vehicle (first 3) or landmark (at o) entries of x_0 + K nu for linearisation L;
 *  returns the largest change against `current`. */
double nextPoint(const PoseLinearisation& L, Eigen::Index o, const Eigen::Vector3d& x0, Eigen::Vector3d& current)
{
    const Eigen::Vector3d Sinv_nu = L.llt.matrixL().transpose().solve(L.y);
    Eigen::Vector3d next = x0 + L.PHt.middleRows<3>(o) * Sinv_nu;
    next.z() = mrpt::math::wrapToPi(next.z());
    Eigen::Vector3d step = next - current;
    step.z() = mrpt::math::wrapToPi(step.z());
    current = next;
    return step.lpNorm<Eigen::Infinity>();
}
/** The mean part of a pose-landmark update: x += K nu with linearisation Lm (the last
 *  iterate's), and the passive blocks' mean (Lm) and covariance (Lc). Returns W^T of Lc (Lm
 *  itself, or the FEJ or one-step update's: Options::iterated_covariance) for
 *  EkfSlam::updateCovariance; empty, with nothing changed, if a gain is not finite. */
Eigen::MatrixXd applyPoseMeanUpdate(Eigen::VectorXd& x, PassiveStates& passive, const PoseLinearisation& Lm,
                                    const PoseLinearisation& Lc, Eigen::Index ov, Eigen::Index o)
{
    const bool one = &Lc == &Lm;
    const Eigen::MatrixXd Wt = Lm.llt.matrixL().solve(Lm.PHt.transpose());
    const Eigen::MatrixXd Wc = one ? Wt : Eigen::MatrixXd(Lc.llt.matrixL().solve(Lc.PHt.transpose()));
    if (!Wt.allFinite() || !Wc.allFinite() || !Lm.y.allFinite()) return {};
    if (passive.numBlocks() > 0)
    {
        const Eigen::MatrixXd Wp = passiveGain(passive, Lm.Hv, Lm.Hl, ov, o, Lm.llt);
        const Eigen::MatrixXd Wpc = one ? Wp : passiveGain(passive, Lc.Hv, Lc.Hl, ov, o, Lc.llt);
        if (!Wp.allFinite() || !Wpc.allFinite()) return {};
        passive.applyMeanUpdate(Wp, Lm.y);
        passive.applyCovarianceUpdate(Wpc, Wc.transpose());
    }
    // x_0 + K nu with the last linearisation's gain and innovation.
    x.noalias() += Wt.transpose() * Lm.y;
    x[2] = mrpt::math::wrapToPi(x[2]);
    x[ov + 2] = mrpt::math::wrapToPi(x[ov + 2]);
    x[o + 2] = mrpt::math::wrapToPi(x[o + 2]);
    return Wc;
}
}  // namespace

std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> EkfSlam::poseFejPoint(long observer, long id) const
{
    if (options_.jacobians != LinearisationPoint::FirstEstimates) return std::nullopt;
    return FejPoint{observer < 0 ? predicted_pose_ : Eigen::Vector3d(first_estimates_.at(observer)),
                    id < 0 ? predicted_pose_ : Eigen::Vector3d(first_estimates_.at(id))};
}

void EkfSlam::poseObservationJacobians(long id, const Eigen::Vector3d& sensor, Eigen::Matrix3d& H_v,
                                       Eigen::Matrix3d& H_l) const
{
    const LandmarkBlock& b = layout_.get(id);
    if (b.dim != 3)
        throw std::invalid_argument("EkfSlam::poseObservationJacobians: landmark " + std::to_string(id) +
                                    " is not a 3-DOF pose block");
    const auto fej = poseFejPoint(-1, id);
    if (fej)
        poseLandmarkObservation(fej->first, fej->second, sensor, &H_v, &H_l);
    else
        poseLandmarkObservation(x_.head<3>(), x_.segment<3>(static_cast<Eigen::Index>(b.offset)), sensor, &H_v, &H_l);
}

PoseUpdateReport EkfSlam::updatePoseLandmark(long id, const Eigen::Vector3d& z,
                                             const Eigen::Matrix3d& R,
                                             const Eigen::Vector3d& sensor, double gate_prob,
                                             int max_iterations)
{
    return updatePoseBlock(-1, id, z, R, sensor, gate_prob, max_iterations);
}

PoseUpdateReport EkfSlam::updateRelativePose(long observer, long id, const Eigen::Vector3d& z,
                                             const Eigen::Matrix3d& R, double gate_prob, int max_iterations)
{
    if (observer == id) throw std::invalid_argument("updateRelativePose: a landmark observed from itself");
    return updatePoseBlock(observer, id, z, R, Eigen::Vector3d::Zero(), gate_prob, max_iterations);
}

PoseUpdateReport EkfSlam::updatePoseBlock(long observer, long id, const Eigen::Vector3d& z, const Eigen::Matrix3d& R,
                                          const Eigen::Vector3d& sensor, double gate_prob, int max_iterations)
{
    PoseUpdateReport rep;
    const auto fail = [&rep](PoseUpdateReport::Outcome o) {
        rep.outcome = o;
        return rep;
    };
    if (!z.allFinite() || !validCovariance3(R)) return fail(PoseUpdateReport::Outcome::invalid);
    const auto offset3 = [this](long b_id)
    {
        const LandmarkBlock& b = layout_.get(b_id);
        if (b.dim != 3)
            throw std::invalid_argument("pose update: landmark " + std::to_string(b_id) + " is not a 3-DOF pose block");
        return static_cast<Eigen::Index>(b.offset);
    };
    // id < 0: the vehicle is the observed block (updateVehicleFromCopy).
    const Eigen::Index o = id < 0 ? 0 : offset3(id), ov = observer < 0 ? 0 : offset3(observer);
    const Eigen::Vector3d xv0 = x_.segment<3>(ov), xl0 = x_.segment<3>(o);
    Eigen::Vector3d xv = xv0, xl = xl0;  // linearisation point (the prior at iteration 0)
    PoseLinearisation L;
    // First-estimates Jacobians for the EKF step; the iterated update relinearises at its
    // iterates by definition (its gate too), so it does not use them here
    // (iterated_covariance below may for its covariance).
    const std::optional<FejPoint> fej = max_iterations <= 1 ? poseFejPoint(observer, id) : std::nullopt;
    for (int it = 0;; ++it)
    {
        if (!linearise(activeP(), ov, o, z, R, sensor, xv0, xl0, xv, xl, fej ? &*fej : nullptr,
                       options_.pose_update_second_order, L))
            return fail(PoseUpdateReport::Outcome::numeric);
        // Thesis 5.5: the aligned observation is verified by a gate before it is used (on
        // the prior's linearisation, as the EKF would).
        if (it == 0) rep.nis = L.y.squaredNorm();
        if (it == 0 && gate_prob > 0 && gate_prob < 1 && rep.nis > mrpt::math::chi2inv(gate_prob, 3))
            return fail(PoseUpdateReport::Outcome::gated);
        if (it + 1 >= max_iterations) break;
        const double moved = std::max(nextPoint(L, ov, xv0, xv), nextPoint(L, o, xl0, xl));
        ++rep.iterations;
        if (moved < 1e-9) break;
    }
    // Options::iterated_covariance = first_estimates: the iterates give the mean (Gauss-Newton
    // on the prior and z, right for a correction of metres and degrees), the covariance the
    // one-step update's Jacobians (FEJ's, or the prior's with the invariant EKF), so that
    // relinearising adds no information along the unobservable directions (Huang et al. 2008).
    const bool one_step_cov =
        rep.iterations > 0 && options_.iterated_covariance == IteratedCovariance::FirstEstimates;
    const std::optional<FejPoint> fej_cov = one_step_cov ? poseFejPoint(observer, id) : std::nullopt;
    PoseLinearisation Lc;
    if (one_step_cov && !linearise(activeP(), ov, o, z, R, sensor, xv0, xl0, xv0, xl0, fej_cov ? &*fej_cov : nullptr,
                                   options_.pose_update_second_order, Lc))
        return fail(PoseUpdateReport::Outcome::numeric);
    const auto prior = invariantPrior();
    const Eigen::MatrixXd Wc = applyPoseMeanUpdate(x_, passive_, L, one_step_cov ? Lc : L, ov, o);
    if (Wc.size() == 0) return fail(PoseUpdateReport::Outcome::numeric);
    // P -= W W^T of Lc (see fuse()), carried by the invariant EKF's M.
    updateCovariance(Wc, prior, rep.iterations == 0);
    if (id >= 0) ++layout_.get(id).times_seen;
    rep.outcome = PoseUpdateReport::Outcome::updated;
    return rep;
}

PoseUpdateReport EkfSlam::updateVehicleFromCopy(long copy, const Eigen::Vector3d& z, const Eigen::Matrix3d& R,
                                                double gate_prob)
{
    if (copy < 0) throw std::invalid_argument("updateVehicleFromCopy: no copy id");
    return updatePoseBlock(copy, -1, z, R, Eigen::Vector3d::Zero(), gate_prob, 1);
}

}  // namespace hymm::ekf
