#include "hymm/ekf/EkfSlam.h"
#include "check_covariance.h"

#include <hymm/core/RangeBearingModel.h>
#include <hymm/core/TimeLogger.h>
#include <hymm/core/turn_bias.h>
#include <hymm/ekf/pose_composition.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace hymm::ekf
{
namespace
{
/** Deletes rows and columns [o, o + d) of the active n x n part of the covariance storage
 *  in place (marginalisation): the later rows and columns move up and left by d. Cost
 *  O(n (n - o)), small for the recent (tentative) landmarks that pruning removes; no
 *  allocation, unlike building a fresh (n - d) x (n - d) matrix. */
void eraseRowsColsInPlace(Eigen::MatrixXd& buf, Eigen::Index n, Eigen::Index o, Eigen::Index d)
{
    const Eigen::Index t = n - o - d;  // rows / columns after the removed ones
    if (t <= 0) return;
    const auto bytes = [](Eigen::Index c) { return static_cast<size_t>(c) * sizeof(double); };
    // Columns before o: only their tail rows move (within the column, overlapping).
    for (Eigen::Index j = 0; j < o; ++j) std::memmove(&buf(o, j), &buf(o + d, j), bytes(t));
    // Later columns move left by d (distinct columns, ascending: a source column is read
    // before any write reaches it), their tail rows up by d.
    for (Eigen::Index j = o; j < n - d; ++j)
    {
        std::memcpy(&buf(0, j), &buf(0, j + d), bytes(o));
        std::memcpy(&buf(o, j), &buf(o + d, j + d), bytes(t));
    }
}

void eraseEntries(Eigen::VectorXd& x, Eigen::Index o, Eigen::Index d)
{
    const Eigen::Index t = x.size() - o - d;
    if (t > 0) x.segment(o, t) = x.tail(t).eval();
    x.conservativeResize(x.size() - d);
}

Eigen::Matrix3d stabilisingNoise(const EkfSlam::Options& o)
{
    return Eigen::Vector3d(o.stabilising_std_xy * o.stabilising_std_xy,
                           o.stabilising_std_xy * o.stabilising_std_xy,
                           o.stabilising_std_phi * o.stabilising_std_phi)
        .asDiagonal();
}

}  // namespace
using detail::checkCovariance;

EkfSlam::EkfSlam(const Options& options)
    : options_(options), profiler_(options.enable_profiler, "hymm::EkfSlam")
{
    options_.validate();
    reset(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero());
}

void EkfSlam::reserveStates(Eigen::Index n)
{
    if (Pbuf_.rows() >= n) return;
    // Geometric growth (1.5x): a growing map reallocates O(log n) times, so appending k
    // rows and columns costs O(n k) amortised instead of a fresh n x n matrix per batch.
    // The spare part is zeroed once so that no entry of the storage is ever indeterminate.
    const Eigen::Index cap = std::max({n, Pbuf_.rows() + Pbuf_.rows() / 2, Eigen::Index{64}});
    Eigen::MatrixXd grown = Eigen::MatrixXd::Zero(cap, cap);
    const Eigen::Index a = x_.size();
    grown.topLeftCorner(a, a) = Pbuf_.topLeftCorner(a, a);
    Pbuf_.swap(grown);
}

void EkfSlam::reset(const Eigen::Vector3d& pose, const Eigen::Matrix3d& cov)
{
    checkCovariance(cov, 3, "EkfSlam::reset");
    if (!pose.allFinite()) throw std::invalid_argument("EkfSlam::reset: non-finite pose");
    layout_.clear();
    passive_.clear();
    first_estimates_.clear();
    reserveStates(3);
    x_ = pose;
    x_[2] = mrpt::math::wrapToPi(x_[2]);
    activeP() = 0.5 * (cov + cov.transpose());
    predicted_pose_ = x_;
    last_F_.setIdentity();
    step_ = 0;
}

// ---------------------------------------------------------------- prediction
void EkfSlam::applyVehicleMotion(const Eigen::Vector3d& pose, const Eigen::Matrix3d& F_current,
                                 const Eigen::Matrix3d& Q, Eigen::Index param, const Eigen::Vector3d& G)
{
    // Eq. 2.36: the map is static, so only P_vv and the vehicle rows/columns change: O(n).
    const Eigen::Index n = x_.size(), nm = n - 3;
    Eigen::Matrix3d F = F_current;
    if (options_.jacobians == LinearisationPoint::FirstEstimates)
    {
        // Both motion models move the position by R(phi_k) g(u), so the standard block is
        // d p_{k+1} / d phi_k = J (p_{k+1|k} - p_{k|k}), J = [0 -1; 1 0]. FEJ-EKF (Huang
        // et al. 2008) takes p_{k|k-1} instead of p_{k|k}: the product of the
        // Jacobians from step j to step k then has the block J (p_{k|k-1} - p_{j|j-1}), as
        // for the true (noise-free) system, which keeps global heading unobservable.
        // Without an update since the last prediction p_{k|k-1} = p_{k|k}: no change.
        const Eigen::Vector2d dp = pose.head<2>() - predicted_pose_.head<2>();
        F(0, 2) = -dp[1];
        F(1, 2) = dp[0];
    }
    last_F_ = F;
    predicted_pose_ = pose;
    x_.head<3>() = pose;
    auto P = activeP();
    if (param >= 3)
    {
        // x_v <- F x_v + G x_param: P <- T P T^T + Q, T the identity but for the vehicle
        // rows [F at v, G at param]. Rows first, then columns (row and column `param` are
        // not changed by T, so neither pass reads what it wrote). O(n).
        P.topRows<3>() = (F * P.topRows<3>() + G * P.row(param)).eval();
        P.leftCols<3>() = (P.leftCols<3>() * F.transpose() + P.col(param) * G.transpose()).eval();
        const Eigen::Matrix3d Pvv = P.topLeftCorner<3, 3>() + Q;
        P.topLeftCorner<3, 3>() = 0.5 * (Pvv + Pvv.transpose());
        passive_.predictVehicle(F, param, G);
        return;
    }
    const Eigen::Matrix3d Pvv = P.topLeftCorner<3, 3>();
    P.topLeftCorner<3, 3>() = F * Pvv * F.transpose() + Q;
    P.topLeftCorner<3, 3>() = (0.5 * (P.topLeftCorner<3, 3>() + P.topLeftCorner<3, 3>().transpose())).eval();
    if (nm > 0)
    {
        P.topRightCorner(3, nm) = (F * P.topRightCorner(3, nm)).eval();
        P.bottomLeftCorner(nm, 3) = P.topRightCorner(3, nm).transpose();
    }
    passive_.predictVehicle(F);
}

void EkfSlam::predictUte(const Eigen::Vector2d& u, const Eigen::Matrix2d& Q, double dt,
                         const hymm::core::UteParams& p)
{
    core::TimedSection tle(profiler_, "ekf.1_predict");
    if (!u.allFinite() || !std::isfinite(dt) || dt < 0.0)
        throw std::invalid_argument("EkfSlam::predictUte: non-finite control or negative dt");
    checkCovariance(Q, 2, "EkfSlam::predictUte(Q)");
    Eigen::Matrix3d F;
    Eigen::Matrix<double, 3, 2> B;
    const Eigen::Vector3d pose = hymm::core::uteStep(x_.head<3>(), u, dt, p, &F, &B);
    // Eq. 2.34-2.35: control noise enters through B; stabilising noise is additive.
    applyVehicleMotion(pose, F, B * Q * B.transpose() + stabilisingNoise(options_));
}

void EkfSlam::predictOdometry(const mrpt::poses::CPosePDFGaussian& increment)
{
    core::TimedSection tle(profiler_, "ekf.1_predict");
    const Eigen::Vector3d d(increment.mean.x(), increment.mean.y(), increment.mean.phi());
    Eigen::Matrix3d Sigma = increment.cov.asEigen();
    if (!d.allFinite()) throw std::invalid_argument("EkfSlam::predictOdometry: non-finite increment");
    checkCovariance(Sigma, 3, "EkfSlam::predictOdometry(increment.cov)");
    Eigen::Matrix3d Jx, Jd;
    const Eigen::Vector3d pose = composePose(x_.head<3>(), d, &Jx, &Jd);
    applyVehicleMotion(pose, Jx, Jd * Sigma * Jd.transpose() + stabilisingNoise(options_));
}

void EkfSlam::predictOdometryWithTurnBias(const mrpt::poses::CPosePDFGaussian& increment, long bias,
                                          double walk_var)
{
    core::TimedSection tle(profiler_, "ekf.1_predict");
    if (options_.jacobians == LinearisationPoint::Invariant)
        throw std::invalid_argument("EkfSlam::predictOdometryWithTurnBias: not available with jacobians = invariant");
    const LandmarkBlock& b = layout_.get(bias);
    if (b.dim != 1) throw std::invalid_argument("EkfSlam::predictOdometryWithTurnBias: the bias block is not 1-DOF");
    if (!(walk_var >= 0) || !std::isfinite(walk_var))
        throw std::invalid_argument("EkfSlam::predictOdometryWithTurnBias: walk_var < 0 or not finite");
    const Eigen::Vector3d d(increment.mean.x(), increment.mean.y(), increment.mean.phi());
    const Eigen::Matrix3d Sigma = increment.cov.asEigen();
    if (!d.allFinite()) throw std::invalid_argument("EkfSlam::predictOdometryWithTurnBias: non-finite increment");
    checkCovariance(Sigma, 3, "EkfSlam::predictOdometryWithTurnBias(increment.cov)");
    const auto o = static_cast<Eigen::Index>(b.offset);
    Eigen::Vector3d Jb;
    Eigen::Matrix3d Jt, Jx, Jd;
    const Eigen::Vector3d du = core::turnBiasedIncrement(d, x_[o], &Jb, &Jt);
    const Eigen::Vector3d pose = composePose(x_.head<3>(), du, &Jx, &Jd);
    const Eigen::Matrix3d JdJt = Jd * Jt;
    applyVehicleMotion(pose, Jx, JdJt * Sigma * JdJt.transpose() + stabilisingNoise(options_), o, Jd * Jb);
    activeP()(o, o) += walk_var * d.head<2>().norm();
}

void EkfSlam::predictOdometry(const mrpt::obs::CActionRobotMovement2D& action)
{
    ASSERTMSG_(action.poseChange.get() != nullptr,
               "EkfSlam::predictOdometry: CActionRobotMovement2D without poseChange PDF");
    mrpt::poses::CPosePDFGaussian g;
    g.copyFrom(*action.poseChange);
    predictOdometry(g);
}


// ---------------------------------------------------------------- augmentation
void EkfSlam::augment(const std::vector<std::pair<long, Eigen::VectorXd>>& blocks,
                      const Eigen::MatrixXd& G, const Eigen::MatrixXd& noise, bool confirmed)
{
    // Eq. 2.53 with Jacobian [I 0; G_v 0] of the augmented state wrt (x, z): the new rows
    // are G_v P_v* and the new diagonal block G_v P_vv G_v^T + G_z R G_z^T. Several blocks
    // at once also get their mutual terms G_va P_vv G_vb^T through the shared vehicle.
    if (G.rows() == 0) return;
    const Eigen::MatrixXd cross = G * activeP().topRows<3>();  // k x n
    const Eigen::MatrixXd Pnn = G * activeP().topLeftCorner<3, 3>() * G.transpose() + noise;
    // Passive rows: cov(x_p, new) = P_pv G_v^T.
    const Eigen::MatrixXd passive_cols = passive_.numBlocks() > 0
                                             ? Eigen::MatrixXd(passive_.crossAll().leftCols<3>() * G.transpose())
                                             : Eigen::MatrixXd();
    appendBlocks(blocks, cross, Pnn, passive_cols, confirmed);
}

void EkfSlam::appendBlocks(const std::vector<std::pair<long, Eigen::VectorXd>>& blocks, const Eigen::MatrixXd& cross,
                           const Eigen::MatrixXd& Pnn, const Eigen::MatrixXd& passive_cols, bool confirmed)
{
    const Eigen::Index n = x_.size(), k = cross.rows();
    if (passive_.numBlocks() > 0) passive_.appendActiveColumns(passive_cols);
    // Rows and columns appended in place into the spare capacity: O(n k).
    reserveStates(n + k);
    x_.conservativeResize(n + k);
    auto P = activeP();
    P.bottomLeftCorner(k, n) = cross;
    P.topRightCorner(n, k) = cross.transpose();
    P.bottomRightCorner(k, k) = 0.5 * (Pnn + Pnn.transpose());
    Eigen::Index row = n;
    for (const auto& [id, mean] : blocks)
    {
        x_.segment(row, mean.size()) = mean;
        LandmarkBlock& b = layout_.get(layout_.add(id, static_cast<int>(mean.size()), step_).id);
        first_estimates_[b.id] = mean;
        b.times_seen = 1;
        b.confirmed = confirmed;
        row += mean.size();
    }
}

long EkfSlam::addLandmark(const Eigen::VectorXd& mean, const Eigen::MatrixXd& G_v,
                          const Eigen::MatrixXd& noise_cov, long id)
{
    const auto d = mean.size();
    if (d < 1 || !mean.allFinite()) throw std::invalid_argument("EkfSlam::addLandmark: bad mean");
    if (G_v.rows() != d || G_v.cols() != 3 || !G_v.allFinite())
        throw std::invalid_argument("EkfSlam::addLandmark: G_v must be dim x 3 and finite");
    checkCovariance(noise_cov, d, "EkfSlam::addLandmark(noise_cov)");
    if (id < 0) id = layout_.nextFreeId();
    if (layout_.has(id))
        throw std::invalid_argument("EkfSlam::addLandmark: id " + std::to_string(id) + " exists");
    augment({{id, mean}}, G_v, noise_cov, true);
    return id;
}

void EkfSlam::removeLandmark(long id)
{
    const LandmarkBlock b = layout_.remove(id);  // throws if unknown
    first_estimates_.erase(id);
    const auto o = static_cast<Eigen::Index>(b.offset), d = static_cast<Eigen::Index>(b.dim);
    eraseRowsColsInPlace(Pbuf_, x_.size(), o, d);
    eraseEntries(x_, o, d);
    passive_.removeActiveColumns(b.offset, static_cast<size_t>(b.dim));
}

// ---------------------------------------------------------------- accessors
Eigen::VectorXd EkfSlam::landmarkBlockMean(long id) const
{
    const LandmarkBlock& b = layout_.get(id);
    return x_.segment(static_cast<Eigen::Index>(b.offset), b.dim);
}

Eigen::MatrixXd EkfSlam::landmarkBlockCov(long id) const
{
    const LandmarkBlock& b = layout_.get(id);
    const auto o = static_cast<Eigen::Index>(b.offset);
    return activeP().block(o, o, b.dim, b.dim);
}

Eigen::Vector2d EkfSlam::landmarkMean(long id) const
{
    if (layout_.get(id).dim != 2)
        throw std::invalid_argument("EkfSlam::landmarkMean: landmark " + std::to_string(id) +
                                    " is not a 2D point");
    return landmarkBlockMean(id);
}

Eigen::Matrix2d EkfSlam::landmarkCov(long id) const
{
    if (layout_.get(id).dim != 2)
        throw std::invalid_argument("EkfSlam::landmarkCov: landmark " + std::to_string(id) +
                                    " is not a 2D point");
    return landmarkBlockCov(id);
}

void EkfSlam::setActiveState(const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                             const std::vector<std::pair<long, int>>& blocks)
{
    StateLayout layout;
    for (const auto& [id, dim] : blocks) layout.add(id, dim, step_);
    if (static_cast<Eigen::Index>(layout.size()) != x.size() || !x.allFinite())
        throw std::invalid_argument("EkfSlam::setActiveState: x size does not match the blocks");
    checkCovariance(P, x.size(), "EkfSlam::setActiveState", false);
    for (auto& b : layout.blocks())
    {
        b.confirmed = true;
        b.times_seen = 1;
    }
    layout_ = layout;
    const Eigen::VectorXd x_new = x;  // x may be mean() itself
    x_.resize(0);  // nothing of the old covariance is kept if the storage grows
    reserveStates(x_new.size());
    x_ = x_new;
    x_[2] = mrpt::math::wrapToPi(x_[2]);
    activeP() = 0.5 * (P + P.transpose());
    passive_.clear();
    first_estimates_.clear();
    for (const auto& b : layout_.blocks())
        first_estimates_[b.id] = x_.segment(static_cast<Eigen::Index>(b.offset), b.dim);
    predicted_pose_ = x_.head<3>();
    last_F_.setIdentity();
}

// ---------------------------------------------------------------- passive states
void EkfSlam::addPassiveState(long id, const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov,
                              const Eigen::MatrixXd& cross_with_active)
{
    passive_.add(id, mean, cov, cross_with_active, static_cast<size_t>(x_.size()));
}

void EkfSlam::addPassiveFromVehicle(long id, const Eigen::VectorXd& mean,
                                    const Eigen::MatrixXd& G_v, const Eigen::MatrixXd& noise_cov)
{
    if (G_v.rows() != mean.size() || G_v.cols() != 3)
        throw std::invalid_argument("EkfSlam::addPassiveFromVehicle: G_v must be dim x 3");
    checkCovariance(noise_cov, mean.size(), "EkfSlam::addPassiveFromVehicle(noise_cov)");
    const Eigen::MatrixXd cov = G_v * activeP().topLeftCorner<3, 3>() * G_v.transpose() + noise_cov;
    passive_.add(id, mean, 0.5 * (cov + cov.transpose()), G_v * activeP().topRows<3>(),
                 static_cast<size_t>(x_.size()));
}

void EkfSlam::addPassiveFromLandmarks(long id, const Eigen::VectorXd& mean,
                                      const std::vector<std::pair<long, Eigen::MatrixXd>>& G,
                                      const Eigen::MatrixXd& noise_cov)
{
    if (G.empty()) throw std::invalid_argument("EkfSlam::addPassiveFromLandmarks: no landmark");
    checkCovariance(noise_cov, mean.size(), "EkfSlam::addPassiveFromLandmarks(noise_cov)");
    std::vector<Eigen::Index> offsets;
    for (const auto& [lid, g] : G)
    {
        const auto& b = landmarkBlock(lid);
        if (g.rows() != mean.size() || g.cols() != static_cast<Eigen::Index>(b.dim))
            throw std::invalid_argument("EkfSlam::addPassiveFromLandmarks: G of landmark " +
                                        std::to_string(lid) + " must be dim x landmark dim");
        offsets.push_back(static_cast<Eigen::Index>(b.offset));
    }
    Eigen::MatrixXd cross = G[0].second * activeP().middleRows(offsets[0], G[0].second.cols());
    for (size_t i = 1; i < G.size(); ++i)
        cross += G[i].second * activeP().middleRows(offsets[i], G[i].second.cols());
    Eigen::MatrixXd cov = cross.middleCols(offsets[0], G[0].second.cols()) * G[0].second.transpose();
    for (size_t i = 1; i < G.size(); ++i)
        cov += cross.middleCols(offsets[i], G[i].second.cols()) * G[i].second.transpose();
    cov += noise_cov;
    passive_.add(id, mean, 0.5 * (cov + cov.transpose()), cross, static_cast<size_t>(x_.size()));
}

}  // namespace hymm::ekf
