// Validation of a covariance handed to the filter (private to hymm::ekf).
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <stdexcept>
#include <string>

namespace hymm::ekf::detail
{
/** Throws std::invalid_argument naming `what` unless C is n x n, finite, symmetric and
 *  (with require_psd) positive semi-definite. */
inline void checkCovariance(const Eigen::MatrixXd& C, Eigen::Index n, const char* what, bool require_psd = true)
{
    if (C.rows() != n || C.cols() != n)
        throw std::invalid_argument(std::string(what) + ": wrong covariance size");
    if (!C.allFinite()) throw std::invalid_argument(std::string(what) + ": non-finite covariance");
    if ((C - C.transpose()).cwiseAbs().maxCoeff() > 1e-9 * (1.0 + C.cwiseAbs().maxCoeff()))
        throw std::invalid_argument(std::string(what) + ": covariance is not symmetric");
    // A negative variance would make the filter's covariance indefinite (and its gates
    // meaningless) from this step on. Not for a whole state handed in (O(n^3)).
    if (!require_psd) return;
    const Eigen::MatrixXd S = 0.5 * (C + C.transpose());
    if (Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S, Eigen::EigenvaluesOnly).eigenvalues().minCoeff() <
        -1e-12 * (1.0 + S.cwiseAbs().maxCoeff()))
        throw std::invalid_argument(std::string(what) + ": covariance is not positive semi-definite");
}

}  // namespace hymm::ekf::detail
