#include "hymm/core/UteVehicleModel.h"

#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hymm::core
{
double uteAxleSpeed(double v_encoder, double steering, const UteParams& p, double* d_dv,
                    double* d_dalpha)
{
    const double t = std::tan(steering);
    const double den = 1.0 - t * p.H / p.L;
    if (std::abs(t) * std::abs(p.H) / p.L >= 0.99)
    {
        std::ostringstream ss;
        ss << "UTE model: steering " << steering << " rad is outside the model's range (H="
           << p.H << ", L=" << p.L << ")";
        throw std::invalid_argument(ss.str());
    }
    const double vc = v_encoder / den;  // Eq. A.3
    if (d_dv) *d_dv = 1.0 / den;
    if (d_dalpha)
    {
        const double sec2 = 1.0 + t * t;
        *d_dalpha = v_encoder * (p.H / p.L) * sec2 / (den * den);
    }
    return vc;
}

Eigen::Vector3d uteStep(
    const Eigen::Vector3d& x, const Eigen::Vector2d& u, double dt, const UteParams& p,
    Eigen::Matrix3d* F, Eigen::Matrix<double, 3, 2>* B)
{
    const double phi = x[2], alpha = u[1];
    double dvc_dv = 0, dvc_da = 0;
    const double vc = uteAxleSpeed(u[0], alpha, p, &dvc_dv, &dvc_da);
    const double t = std::tan(alpha), sec2 = 1.0 + t * t;
    const double w = vc * t / p.L;  // heading rate (Eq. A.1)
    const double c = std::cos(phi), s = std::sin(phi);
    const double T1 = p.a * s + p.b * c;  // Eq. A.13
    const double T2 = p.a * c - p.b * s;  // Eq. A.14

    Eigen::Vector3d xn;  // Eq. A.4
    xn[0] = x[0] + dt * (vc * c - w * T1);
    xn[1] = x[1] + dt * (vc * s + w * T2);
    xn[2] = mrpt::math::wrapToPi(phi + dt * w);

    if (F)
    {  // Eq. A.15
        F->setIdentity();
        (*F)(0, 2) = -dt * (vc * s + w * T2);
        (*F)(1, 2) = dt * (vc * c - w * T1);
    }
    if (B)
    {  // Eq. A.5-A.11, derived: w = vc tan(alpha) / L
        const double dw_dv = dvc_dv * t / p.L;
        const double dw_da = (dvc_da * t + vc * sec2) / p.L;
        (*B)(0, 0) = dt * (dvc_dv * c - dw_dv * T1);
        (*B)(0, 1) = dt * (dvc_da * c - dw_da * T1);
        (*B)(1, 0) = dt * (dvc_dv * s + dw_dv * T2);
        (*B)(1, 1) = dt * (dvc_da * s + dw_da * T2);
        (*B)(2, 0) = dt * dw_dv;
        (*B)(2, 1) = dt * dw_da;
    }
    return xn;
}

Eigen::Vector3d uteIncrement(
    const Eigen::Vector2d& u, double dt, const UteParams& p, Eigen::Matrix<double, 3, 2>* J_u)
{
    double dvc_dv = 0, dvc_da = 0;
    const double vc = uteAxleSpeed(u[0], u[1], p, &dvc_dv, &dvc_da);
    const double t = std::tan(u[1]), sec2 = 1.0 + t * t;
    const double w = vc * t / p.L;
    // Eq. A.4 rotated into the frame of the tracked point at the start of the step.
    Eigen::Vector3d d(dt * (vc - w * p.b), dt * w * p.a, dt * w);
    if (J_u)
    {
        const double dw_dv = dvc_dv * t / p.L;
        const double dw_da = (dvc_da * t + vc * sec2) / p.L;
        (*J_u) << dt * (dvc_dv - dw_dv * p.b), dt * (dvc_da - dw_da * p.b),  //
            dt * dw_dv * p.a, dt * dw_da * p.a,                              //
            dt * dw_dv, dt * dw_da;
    }
    return d;
}

Eigen::Vector3d uteIncrementNoiseBias(
    const Eigen::Vector2d& u, double dt, const UteParams& p, const Eigen::Matrix2d& Q)
{
    uteAxleSpeed(u[0], u[1], p);  // the same range check as the increment itself
    // v_c = v h(alpha), w = v g(alpha) / L with h = 1/den, g = tan(alpha)/den,
    // den = 1 - k tan(alpha), k = H/L (Eq. A.3, A.1). Derived (den + k t = 1):
    //   g' = sec^2/den^2,  h' = k g',  g'' = 2 sec^2 (t den + k sec^2)/den^3,  h'' = k g''.
    const double t = std::tan(u[1]), sec2 = 1.0 + t * t, k = p.H / p.L;
    const double den = 1.0 - k * t;
    const double g1 = sec2 / (den * den);
    const double g2 = 2.0 * sec2 * (t * den + k * sec2) / (den * den * den);
    // Second derivatives of (v_c, w): d2/dalpha2 and d2/dv dalpha (d2/dv2 = 0).
    const double vc_aa = u[0] * k * g2, vc_va = k * g1;
    const double w_aa = u[0] * g2 / p.L, w_va = g1 / p.L;
    const double vc_bias = 0.5 * (Q(1, 1) * vc_aa + (Q(0, 1) + Q(1, 0)) * vc_va);
    const double w_bias = 0.5 * (Q(1, 1) * w_aa + (Q(0, 1) + Q(1, 0)) * w_va);
    // The increment (Eq. A.4 in the tracked point's frame) is linear in (v_c, w).
    return Eigen::Vector3d(dt * (vc_bias - w_bias * p.b), dt * w_bias * p.a, dt * w_bias);
}

}  // namespace hymm::core
