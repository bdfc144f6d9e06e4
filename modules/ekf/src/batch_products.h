// The products of a batch of point-landmark observations with the covariance, gathered
// block by block (private to hymm::ekf). `Pairings` is a vector of EkfSlam's pairings:
// each has the landmark's state offset and the Jacobians Hv (2x3) and Hl (2x2).
#pragma once

#include <Eigen/Core>
#include <cstddef>

namespace hymm::ekf::detail
{
/** P H^T from the vehicle columns and one landmark block per pairing: O(n m) instead of a
 *  dense H times P. P has the state's columns (the active covariance, or the passive
 *  blocks' cross-covariance). */
template <class Matrix, class Pairings>
Eigen::MatrixXd gatherPHt(const Matrix& P, const Pairings& pairs)
{
    Eigen::MatrixXd PHt(P.rows(), static_cast<Eigen::Index>(2 * pairs.size()));
    for (size_t a = 0; a < pairs.size(); ++a)
    {
        const auto& pr = pairs[a];
        const auto o = static_cast<Eigen::Index>(pr.offset);
        PHt.template middleCols<2>(static_cast<Eigen::Index>(2 * a)).noalias() =
            P.template leftCols<3>() * pr.Hv.transpose() + P.template middleCols<2>(o) * pr.Hl.transpose();
    }
    return PHt;
}

/** H P H^T (Eq. 2.39 without R), its rows taken from P H^T = gatherPHt(P, pairs). */
template <class Pairings>
Eigen::MatrixXd projectPHt(const Eigen::MatrixXd& PHt, const Pairings& pairs)
{
    const auto M = static_cast<Eigen::Index>(2 * pairs.size());
    Eigen::MatrixXd C(M, M);
    for (size_t a = 0; a < pairs.size(); ++a)
    {
        const auto& pr = pairs[a];
        C.middleRows<2>(static_cast<Eigen::Index>(2 * a)).noalias() =
            pr.Hv * PHt.topRows<3>() + pr.Hl * PHt.middleRows<2>(static_cast<Eigen::Index>(pr.offset));
    }
    return C;
}
}  // namespace hymm::ekf::detail
