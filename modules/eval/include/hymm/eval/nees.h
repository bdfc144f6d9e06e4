/**
 * @file nees.h
 * @brief Normalised estimation error squared (NEES) and its chi-square consistency bounds.
 *
 * For a consistent filter the NEES e' P^-1 e of a d-dimensional error is chi-square with d
 * degrees of freedom; the average over N Monte Carlo runs, times N, is chi-square with d*N
 * degrees of freedom (Bar-Shalom, Li & Kirubarajan, Sec. 5.4). The two-sided bounds at
 * confidence c of the N-run average are therefore
 *     [ chi2inv((1-c)/2, dN) / N ,  chi2inv((1+c)/2, dN) / N ].
 *
 * Quantiles are computed exactly here (inverting the regularised incomplete gamma
 * function). mrpt::math::chi2inv uses the Wilson-Hilferty approximation: good to about
 * 1e-4 relative for dN >= 100, but poor in the lower tail for small dN (chi2inv(0.025, 3)
 * gives 0.181 instead of 0.2158, and a negative value for dN = 1).
 */
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace hymm::eval
{
enum class NeesStatus
{
    Ok,
    Singular,   //!< covariance not positive definite (or too ill-conditioned to invert)
    NotFinite,  //!< NaN/inf in the error or the covariance
};

struct NeesValue
{
    double value = 0;  //!< NaN unless status == Ok
    NeesStatus status = NeesStatus::Ok;
    bool ok() const { return status == NeesStatus::Ok; }
};

/**
 * NEES e' P^-1 e. P is symmetrised and eigen-decomposed; it counts as singular when its
 * smallest eigenvalue is <= `min_rcond` times the largest (or the largest is <= 0).
 * Throws std::invalid_argument if the sizes do not match or are zero.
 */
NeesValue nees(const Eigen::VectorXd& error, const Eigen::MatrixXd& cov, double min_rcond = 1e-12);

/** CDF of the chi-square distribution with `dof` degrees of freedom (dof > 0). */
double chi2Cdf(double x, double dof);

/** Exact chi-square quantile: x with chi2Cdf(x, dof) = p, for 0 < p < 1 and dof > 0. */
double chi2Quantile(double p, double dof);

/** Wilson-Hilferty approximation of the quantile (the method of mrpt::math::chi2inv). */
double chi2QuantileWilsonHilferty(double p, double dof);

/** Standard normal quantile (p in (0, 1)). */
double normalQuantile(double p);

struct NeesBounds
{
    double lower = 0;
    double upper = 0;
    bool contains(double v) const { return v >= lower && v <= upper; }
};

/**
 * Two-sided bounds of the NEES averaged over `runs` runs of a `dim`-dimensional error at
 * confidence `confidence` (e.g. 0.95). Throws std::invalid_argument on dim < 1, runs < 1
 * or confidence outside (0, 1).
 */
NeesBounds averageNeesBounds(int dim, int runs, double confidence);

/**
 * Fraction of the finite entries of `series` (per-step averaged NEES) inside `bounds`.
 * Non-finite entries (steps where no NEES could be computed) are ignored; returns NaN
 * when no entry is finite.
 */
double fractionInsideBounds(const std::vector<double>& series, const NeesBounds& bounds);

}  // namespace hymm::eval
