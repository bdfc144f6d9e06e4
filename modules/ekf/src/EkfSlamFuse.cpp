// EkfSlam: the pairings of observations with landmarks (predicted observations and
// Jacobians) and the batched Kalman update.
#include <hymm/core/RangeBearingModel.h>
#include <hymm/ekf/EkfSlam.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <optional>
#include <string>

#include "batch_products.h"
#include "se2_retraction.h"

namespace hymm::ekf
{
namespace
{
/** Copies the strict lower triangle onto the upper one in cache-sized tiles (a plain
 *  row-by-row copy reads P with stride n and costs as much as a tenth of the update). */
void mirrorLowerToUpper(Eigen::Ref<Eigen::MatrixXd> P)
{
    constexpr Eigen::Index kTile = 64;
    const Eigen::Index n = P.rows();
    for (Eigen::Index j0 = 0; j0 < n; j0 += kTile)
    {
        const Eigen::Index w = std::min(kTile, n - j0);
        // Diagonal tile: element by element.
        for (Eigen::Index j = j0 + 1; j < j0 + w; ++j)
            for (Eigen::Index i = j0; i < j; ++i) P(i, j) = P(j, i);
        // Tiles below the diagonal tile, transposed into the tiles right of it.
        for (Eigen::Index i0 = j0 + w; i0 < n; i0 += kTile)
        {
            const Eigen::Index h = std::min(kTile, n - i0);
            P.block(j0, i0, w, h) = P.block(i0, j0, h, w).transpose();
        }
    }
}
}  // namespace

EkfSlam::Pairing EkfSlam::makePairing(
    size_t obs, const LandmarkBlock& b, const Eigen::Vector3d& sensor) const
{
    Pairing pr;
    pr.obs = obs;
    pr.offset = b.offset;
    pr.id = b.id;
    const auto o = static_cast<Eigen::Index>(b.offset);
    if (options_.jacobians == LinearisationPoint::FirstEstimates)
    {
        // FEJ-EKF (Huang et al. 2008): the predicted observation (hence the
        // innovation) at the current estimate, the Jacobians at x_{k|k-1} and at the
        // landmark's first estimate.
        pr.h = hymm::core::observeRangeBearing(x_.head<3>(), sensor, x_.segment<2>(o));
        const Eigen::Vector2d first = first_estimates_.at(b.id);
        hymm::core::observeRangeBearing(predicted_pose_, sensor, first, &pr.Hv, &pr.Hl);
    }
    else
        pr.h = hymm::core::observeRangeBearing(
            x_.head<3>(), sensor, x_.segment<2>(o), &pr.Hv, &pr.Hl);
    return pr;
}

void EkfSlam::observationJacobians(long id, const Eigen::Vector3d& sensor,
                                   Eigen::Matrix<double, 2, 3>& H_v, Eigen::Matrix2d& H_l) const
{
    const LandmarkBlock& b = layout_.get(id);
    if (b.dim != 2)
        throw std::invalid_argument("EkfSlam::observationJacobians: landmark " +
                                    std::to_string(id) + " is not a 2D point");
    const Pairing pr = makePairing(0, b, sensor);
    H_v = pr.Hv;
    H_l = pr.Hl;
}

const Eigen::VectorXd& EkfSlam::landmarkFirstEstimate(long id) const
{
    layout_.get(id);  // throws if unknown
    return first_estimates_.at(id);
}

bool EkfSlam::fuse(
    const std::vector<Pairing>& pairs, const std::vector<RangeBearingObs>& obs, std::string& reason)
{
    // P H^T gathered from the vehicle columns and one landmark block per observation.
    const Eigen::MatrixXd PHt = detail::gatherPHt(activeP(), pairs);
    // S = H P H^T + R (Eq. 2.39), rows taken from P H^T; innovation with wrapped bearing.
    Eigen::MatrixXd S = detail::projectPHt(PHt, pairs);
    Eigen::VectorXd nu(S.rows());
    for (size_t a = 0; a < pairs.size(); ++a)
    {
        const auto& pr = pairs[a];
        const auto r = static_cast<Eigen::Index>(2 * a);
        S.block<2, 2>(r, r) += obs[pr.obs].R;
        nu.segment<2>(r) = rangeBearingInnovation(obs[pr.obs].z, pr.h);
    }
    S = (0.5 * (S + S.transpose())).eval();

    Eigen::LLT<Eigen::MatrixXd> llt(S);
    if (llt.info() != Eigen::Success)
    {
        reason = "innovation covariance S of the batch is not positive definite";
        return false;
    }
    // W = P H^T L^-T, so K = W L^-1 and K S K^T = W W^T (Eq. 2.44-2.47). Stored transposed.
    const Eigen::MatrixXd Wt = llt.matrixL().solve(PHt.transpose());
    const Eigen::VectorXd y = llt.matrixL().solve(nu);
    if (!Wt.allFinite() || !y.allFinite())
    {
        reason = "non-finite Kalman gain";
        return false;
    }
    const auto prior = invariantPrior();
    // Passive blocks see the same gain through their cross-covariance (read before P moves).
    if (passive_.numBlocks() > 0)
    {
        const Eigen::MatrixXd PpHt = detail::gatherPHt(passive_.crossAll(), pairs);
        const Eigen::MatrixXd Wp = llt.matrixL().solve(PpHt.transpose()).transpose();
        passive_.applyUpdate(Wp, Wt.transpose(), y);
    }

    x_.noalias() += Wt.transpose() * y;
    x_[2] = mrpt::math::wrapToPi(x_[2]);
    // P -= W W^T as one symmetric rank-M update of the lower triangle (n^2 M flops), then
    // mirrored. This is algebraically the Joseph form for the optimal gain, keeps P exactly
    // symmetric and subtracts a PSD term built from a Cholesky factor; the explicit Joseph
    // form (I-KH)P(I-KH)^T + KRK^T would cost O(n^3) with a dense I-KH.
    updateCovariance(Wt, prior, true);
    return true;
}

std::optional<EkfSlam::PriorMeans> EkfSlam::invariantPrior() const
{
    if (options_.jacobians != LinearisationPoint::Invariant) return std::nullopt;
    return PriorMeans{x_, passive_.meanAll()};
}

void EkfSlam::updateCovariance(const Eigen::MatrixXd& Wt, const std::optional<PriorMeans>& prior, bool retract_mean)
{
    auto P = activeP();
    if (!prior)
    {
        P.selfadjointView<Eigen::Lower>().rankUpdate(Wt.transpose(), -1.0);
        mirrorLowerToUpper(P);
        return;
    }
    // Right-invariant EKF (LinearisationPoint::Invariant). The standard update from the
    // prior with gain factor W (x_ already holds x- + K nu) is the invariant one written in
    // (x, y, phi): with xi_p = dp - dphi_v J p the gain is T K and the posterior T P+ T^T,
    // P+ = P - W W^T. Applied on the group, X+ = exp(xi) X, a position moves by V(w) dp (w
    // the vehicle's heading correction; exp's identity R(w) p - w V J p = p), and the
    // posterior written at the new estimate is M P+ M^T, M = T(x+)^-1 T(x-) = I + b e_phi^T,
    // b = J (p+ - p-).
    const Eigen::Matrix2d V = retract_mean ? detail::se2V(mrpt::math::wrapToPi(x_[2] - prior->active[2]))
                                           : Eigen::Matrix2d::Identity();
    const Eigen::Index n = x_.size(), m = Wt.rows();
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    detail::retractPosition(x_, prior->active, V, 0, b);
    for (const LandmarkBlock& blk : layout_.blocks())
        if (blk.dim >= 2) detail::retractPosition(x_, prior->active, V, static_cast<Eigen::Index>(blk.offset), b);
    // c+ = P+ e and sigma+ = e^T P+ e of the posterior, from P (still the prior) and W.
    const Eigen::VectorXd col = P.col(2) - Wt.transpose() * Wt.col(2);
    const double sigma = P(2, 2) - Wt.col(2).squaredNorm();
    passive_.invariantRetraction(prior->passive, V, b, col, sigma);
    // M P+ M^T = P - W W^T + b c^T + c b^T + sigma b b^T = P + X Y^T with X = [-W, b, c'],
    // Y = [W, c', b], c' = c+ + sigma+ b / 2: one blocked pass over the lower triangle (the
    // Kalman update's own, two columns wider), then mirrored.
    Eigen::MatrixXd X(n, m + 2), Y(n, m + 2);
    const Eigen::VectorXd c2 = col + 0.5 * sigma * b;
    X << -Wt.transpose(), b, c2;
    Y << Wt.transpose(), c2, b;
    P.triangularView<Eigen::Lower>() += X * Y.transpose();
    mirrorLowerToUpper(P);
}

}  // namespace hymm::ekf
