// A check shared by the pipeline (odometry covariances) and the bearing-range source.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace hymm::denseslam
{
/** A symmetric positive semi-definite covariance whose standard deviations stay within
 *  `max_std` (per axis). */
template <int N>
bool usableCovariance(const Eigen::Matrix<double, N, N>& C, const Eigen::Matrix<double, N, 1>& max_std)
{
    if (!C.allFinite() || (C - C.transpose()).cwiseAbs().maxCoeff() > 1e-9 * (1.0 + C.cwiseAbs().maxCoeff()))
        return false;
    if ((C.diagonal().array() > max_std.array().square()).any()) return false;
    const Eigen::Matrix<double, N, N> S = 0.5 * (C + C.transpose());
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>>(S, Eigen::EigenvaluesOnly)
               .eigenvalues()
               .minCoeff() >= -1e-12 * (1.0 + S.cwiseAbs().maxCoeff());
}

}  // namespace hymm::denseslam
