#include "hymm/dense/sensor_models.h"

#include "hymm/dense/RegionScan.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace hymm::dense
{
void validateNoise(const RangeBearingNoise& noise, const char* who)
{
    const auto check = [&](const char* name, double v) {
        if (!(std::isfinite(v) && v > 0))
            throw std::invalid_argument(
                std::string(who) + ": " + name + "=" + std::to_string(v) + " must be finite and > 0");
    };
    check("range_std_m", noise.range_std_m);
    check("bearing_std_rad", noise.bearing_std_rad);
}

RangeBearingNoise effectiveNoise(const RegionScan& scan, const RangeBearingNoise& fallback)
{
    const auto check = [](const char* name, double v) {
        if (!(v >= 0))  // also rejects NaN
            throw std::invalid_argument(
                std::string("RegionScan: ") + name + "=" + std::to_string(v) +
                " must be >= 0 (0 = use the layer's configured noise)");
    };
    check("range_std_m", scan.range_std_m);
    check("bearing_std_rad", scan.bearing_std_rad);
    RangeBearingNoise n = fallback;
    if (scan.range_std_m > 0) n.range_std_m = scan.range_std_m;
    if (scan.bearing_std_rad > 0) n.bearing_std_rad = scan.bearing_std_rad;
    validateNoise(n, "effectiveNoise");
    return n;
}

double normalisedSensorModel(double d_range, double d_bearing, const RangeBearingNoise& noise)
{
    const double a = d_range / noise.range_std_m, b = d_bearing / noise.bearing_std_rad;
    return std::exp(-0.5 * (a * a + b * b));
}

double occupancyModel(
    double rho, double phi, double z_r, double z_theta, bool has_return,
    const RangeBearingNoise& noise, const OccupancyProfile& profile)
{
    const double dphi = std::remainder(phi - z_theta, 2 * M_PI);
    const double lambda_r = has_return ? normalisedSensorModel(rho - z_r, dphi, noise) : 0.0;
    const double lambda = 1.0 - 2.0 * lambda_r;
    if (has_return && lambda <= 0) return 0.5 - (profile.p_max - 0.5) * lambda;
    if (rho <= z_r)
    {
        const double b = dphi / noise.bearing_std_rad;
        return 0.5 + (profile.p_min - 0.5) * lambda * std::exp(-0.5 * b * b);
    }
    return 0.5;
}

Eigen::Matrix2d polarToCartesianJacobian(double r, double theta)
{
    const double c = std::cos(theta), s = std::sin(theta);
    Eigen::Matrix2d j;
    j << c, -r * s, s, r * c;
    return j;
}

Eigen::Matrix2d polarToCartesianCovariance(double r, double theta, const RangeBearingNoise& noise)
{
    const Eigen::Matrix2d j = polarToCartesianJacobian(r, theta);
    const Eigen::Vector2d var(
        noise.range_std_m * noise.range_std_m, noise.bearing_std_rad * noise.bearing_std_rad);
    return transformCovariance(j, var.asDiagonal().toDenseMatrix());
}

double bayesOccupancyUpdate(double p_prior, double p_obs)
{
    const double num = p_obs * p_prior;
    return num / (num + (1.0 - p_obs) * (1.0 - p_prior));
}

Eigen::Matrix2d transformCovariance(const Eigen::Matrix2d& a, const Eigen::Matrix2d& p)
{
    const Eigen::Matrix2d q = a * p * a.transpose();
    return 0.5 * (q + q.transpose());
}

}  // namespace hymm::dense
