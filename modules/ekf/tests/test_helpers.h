// Shared helpers of the ekf tests: numeric Jacobians, random SPD matrices, a filter
// state built from known landmark observations.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>

#include <cmath>
#include <vector>

#include <functional>
#include <random>

namespace hymm::ekf::testing
{
/** Central-difference Jacobian of f at x; `wrap_rows` lists output rows that are angles. */
inline Eigen::MatrixXd numericJacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
    const std::vector<int>& wrap_rows = {}, double step = 1e-6)
{
    const Eigen::VectorXd f0 = f(x);
    Eigen::MatrixXd J(f0.size(), x.size());
    for (Eigen::Index j = 0; j < x.size(); ++j)
    {
        Eigen::VectorXd xp = x, xm = x;
        xp[j] += step;
        xm[j] -= step;
        Eigen::VectorXd d = f(xp) - f(xm);
        for (int r : wrap_rows) d[r] = std::remainder(d[r], 2.0 * M_PI);
        J.col(j) = d / (2.0 * step);
    }
    return J;
}

/** Random symmetric positive definite matrix with eigenvalues in [lo, hi]. */
inline Eigen::MatrixXd randomSpd(std::mt19937& rng, Eigen::Index n, double lo, double hi)
{
    std::normal_distribution<double> g(0.0, 1.0);
    std::uniform_real_distribution<double> u(lo, hi);
    Eigen::MatrixXd A(n, n);
    for (Eigen::Index i = 0; i < A.size(); ++i) A.data()[i] = g(rng);
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(A);
    const Eigen::MatrixXd Q = qr.householderQ();
    Eigen::VectorXd ev(n);
    for (Eigen::Index i = 0; i < n; ++i) ev[i] = u(rng);
    Eigen::MatrixXd S = Q * ev.asDiagonal() * Q.transpose();
    return 0.5 * (S + S.transpose());
}

inline double minEigenvalue(const Eigen::MatrixXd& P)
{
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P, Eigen::EigenvaluesOnly)
        .eigenvalues()
        .minCoeff();
}

}  // namespace hymm::ekf::testing
