/**
 * @file sensor_models.h
 * @brief Range-bearing sensor model, its occupancy model and its Cartesian covariance
 *        (thesis Eq. 4.1-4.5, 4.8-4.9, 4.15-4.16), shared by the particle and SOG layers.
 *
 * Transcription notes (verified by derivation and by tests in sensor_models_test.cpp):
 *  - Eq. 4.1/4.2 as printed put the exponential inside the normaliser and divide the
 *    squared residuals by sigma_r and sigma_theta. The bivariate Gaussian with
 *    R = diag(sigma_r^2, sigma_theta^2) (Eq. 2.41) is
 *      P(r|z) = 1 / (2 pi sigma_r sigma_theta) exp(-1/2 [(r_r-z_r)^2/sigma_r^2 + (r_t-z_t)^2/sigma_t^2]).
 *    Only the normalised form (peak 1, "lambda_r" of Eq. 4.4) is used here.
 *  - Eq. 4.5 defines r_u by 0.5 + (p_min - 0.5) lambda = 0.5, i.e. lambda = 0, which
 *    holds on BOTH sides of the peak (lambda_r = 0.5). The near solution would leave the
 *    whole free space "unknown", contradicting Fig. 4.1; r_u is therefore the far one,
 *    r_u = z_r + sigma_r sqrt(2 ln 2): in front of the peak the model falls to p_min,
 *    behind it returns to 0.5 (unknown).
 */
#pragma once

#include <Eigen/Core>

namespace hymm::dense
{
struct RegionScan;

/** Independent Gaussian noise of a range-bearing return (Eq. 2.41). */
struct RangeBearingNoise
{
    double range_std_m = 0.1;      //!< [m] (Table 4.1)
    double bearing_std_rad = 0.0174532925199432957;  //!< [rad] 1 deg (Table 4.1)
};

/** Throws std::invalid_argument unless both stds are finite and > 0; `who` prefixes
 *  the message. */
void validateNoise(const RangeBearingNoise& noise, const char* who);

/** The scan's noise where it carries one (> 0), else `fallback`'s; throws
 *  std::invalid_argument on a negative/NaN scan noise. */
RangeBearingNoise effectiveNoise(const RegionScan& scan, const RangeBearingNoise& fallback);

/** Maximum and minimum of the occupancy model (Eq. 4.4). */
struct OccupancyProfile
{
    double p_min = 0.3;  //!< occupancy deep in the free space of a beam, < 0.5
    double p_max = 0.9;  //!< occupancy at the return, > 0.5
};

/** lambda_r: the sensor model of Eq. 4.2 normalised to peak 1, for residuals in range
 *  [m] and bearing [rad] (bearing residual already wrapped). */
double normalisedSensorModel(double d_range, double d_bearing, const RangeBearingNoise& noise);

/** P(occupied) at polar position (rho, phi) relative to the sensor given a return at
 *  (z_r, z_theta) (Eq. 4.4 extended to range-bearing; Eq. 4.8-4.9 evaluate samples in
 *  it). With lambda = 1 - 2 lambda_r:
 *   - lambda <= 0 (peak):                P = 0.5 - (p_max - 0.5) lambda
 *   - lambda > 0, rho <= z_r (in front): P = 0.5 + (p_min - 0.5) lambda a(phi)
 *   - otherwise (behind, r > r_u):       P = 0.5
 *  a(phi) = exp(-dphi^2 / (2 sigma_theta^2)) confines the free space to the beam's cone
 *  (the printed 1D model has no bearing). When `has_return` is false the beam ended at
 *  max range z_r with no return: the free branch holds for rho <= z_r with lambda = 1. */
double occupancyModel(
    double rho, double phi, double z_r, double z_theta, bool has_return,
    const RangeBearingNoise& noise, const OccupancyProfile& profile);

/** Jacobian of Eq. 4.15, f(r, theta) = (r cos theta, r sin theta), w.r.t. (r, theta). */
Eigen::Matrix2d polarToCartesianJacobian(double r, double theta);

/** Eq. 4.16: P = J R J^T with R = diag(sigma_r^2, sigma_theta^2), symmetrised. */
Eigen::Matrix2d polarToCartesianCovariance(double r, double theta, const RangeBearingNoise& noise);

/** Binary Bayes update of Eq. 4.6 / 4.11 with an inverse-model probability `p_obs` on
 *  a prior `p_prior` (uniform 0.5 prior on the cell state):
 *  p_obs p / (p_obs p + (1 - p_obs)(1 - p)). */
double bayesOccupancyUpdate(double p_prior, double p_obs);

/** A x A^T, symmetrised (keeps a transformed covariance exactly symmetric). */
Eigen::Matrix2d transformCovariance(const Eigen::Matrix2d& a, const Eigen::Matrix2d& p);

}  // namespace hymm::dense
