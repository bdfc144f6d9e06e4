/**
 * @file NoiseCalibrationOdometry.cpp
 * @brief Maximum-likelihood control noise over odometry windows against a ground-truth
 *        track, and the systematic errors (delay, scale, offset) of the commands.
 */
#include "hymm/datasets/NoiseCalibration.h"

#include <hymm/core/config_utils.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include "noise_calibration_track.h"

namespace hymm::datasets
{
namespace
{
using detail::kMinTruthStd;
using detail::madStd;
using detail::median;
using detail::Track;
using detail::Window;
using detail::WindowInputs;
using hymm::io::StampedPose2D;
using OI = OdometryIntegrator;
using detail::fitCommandBias;
using detail::makeWindows;

constexpr double kChi2Dof3P95 = 7.814728;  // chi2 inverse CDF, 3 DOF, 0.95
constexpr int kMaxIterations = 200;

/** Ground-truth noise (std_xy, std_phi) from second differences of evenly spaced,
 *  clean triples: for white noise of std s, x[i+1] - 2 x[i] + x[i-1] has std s sqrt(6). */
std::pair<double, double> truthNoise(const Track& track)
{
    std::vector<double> dxy, dphi;
    for (size_t i = 1; i + 1 < track.size(); ++i)
    {
        const auto &a = track[i - 1], &b = track[i], &c = track[i + 1];
        if (!track.clean(i - 1, i + 1) || std::abs((c.t - b.t) - (b.t - a.t)) > 1e-6) continue;
        dxy.push_back(c.x - 2 * b.x + a.x);
        dxy.push_back(c.y - 2 * b.y + a.y);
        dphi.push_back(mrpt::math::wrapToPi(c.phi - b.phi) - mrpt::math::wrapToPi(b.phi - a.phi));
    }
    if (dxy.empty()) return {kMinTruthStd, kMinTruthStd};
    return {std::max(kMinTruthStd, madStd(dxy, median(dxy)) / std::sqrt(6.0)),
            std::max(kMinTruthStd, madStd(dphi, median(dphi)) / std::sqrt(6.0))};
}

/**
 * Maximum likelihood of theta = (var_speed, var_turn) for r_j ~ N(0, t1 A_j + t2 B_j +
 * V_j) by Fisher scoring: score s_m = 1/2 sum (r' S^-1 G_m S^-1 r - tr(S^-1 G_m)),
 * information I_mn = 1/2 sum tr(S^-1 G_m S^-1 G_n), theta += I^-1 s (halved while the
 * likelihood drops, kept positive).
 */
struct MlFit
{
    Eigen::Vector2d theta;
    Eigen::Matrix2d info;
    size_t iterations = 0;
};

double logLik(const std::vector<const Window*>& ws, const Eigen::Vector2d& th)
{
    double L = 0;
    for (const auto* w : ws)
    {
        const Eigen::Matrix3d S = th[0] * w->A + th[1] * w->B + w->V;
        const Eigen::LDLT<Eigen::Matrix3d> ldlt(S);
        L -= 0.5 * (ldlt.vectorD().array().log().sum() + w->r.dot(ldlt.solve(w->r)));
    }
    return L;
}

MlFit fitMl(const std::vector<const Window*>& ws)
{
    // Moment start: heading variance -> turn, along-track variance -> speed.
    double rp = 0, bp = 0, vp = 0, rx = 0, ax = 0, vx = 0;
    for (const auto* w : ws)
    {
        rp += w->r[2] * w->r[2], bp += w->B(2, 2), vp += w->V(2, 2);
        rx += w->r[0] * w->r[0], ax += w->A(0, 0), vx += w->V(0, 0);
    }
    MlFit f;
    f.theta << std::max((rx - vx) / ax, 1e-3 * rx / ax + 1e-12),
        std::max((rp - vp) / bp, 1e-3 * rp / bp + 1e-12);
    double L = logLik(ws, f.theta);
    for (int it = 0; it < kMaxIterations; ++it)
    {
        Eigen::Vector2d score = Eigen::Vector2d::Zero();
        Eigen::Matrix2d info = Eigen::Matrix2d::Zero();
        for (const auto* w : ws)
        {
            const Eigen::Matrix3d S = f.theta[0] * w->A + f.theta[1] * w->B + w->V;
            const Eigen::LDLT<Eigen::Matrix3d> ldlt(S);
            const Eigen::Vector3d a = ldlt.solve(w->r);
            const Eigen::Matrix3d SA = ldlt.solve(w->A), SB = ldlt.solve(w->B);
            score[0] += 0.5 * (a.dot(w->A * a) - SA.trace());
            score[1] += 0.5 * (a.dot(w->B * a) - SB.trace());
            info(0, 0) += 0.5 * (SA * SA).trace();
            info(1, 1) += 0.5 * (SB * SB).trace();
            info(0, 1) += 0.5 * (SA * SB).trace();
        }
        info(1, 0) = info(0, 1);
        f.info = info;
        f.iterations = static_cast<size_t>(it) + 1;
        Eigen::Vector2d step = info.ldlt().solve(score);
        Eigen::Vector2d next = f.theta;
        double Ln = -std::numeric_limits<double>::infinity();
        for (int h = 0; h < 30; ++h)
        {
            for (int m = 0; m < 2; ++m)
                next[m] = std::max(f.theta[m] + step[m], 0.1 * f.theta[m]);
            Ln = logLik(ws, next);
            if (Ln >= L - 1e-12 * std::abs(L)) break;
            step *= 0.5;
        }
        const bool done = ((next - f.theta).array().abs() <= 1e-9 * f.theta.array()).all();
        if (Ln >= L - 1e-12 * std::abs(L)) f.theta = next, L = Ln;
        if (done) break;
    }
    return f;
}

OdometryNoiseFit describe(const std::vector<const Window*>& ws, const MlFit& f, double window_s)
{
    OdometryNoiseFit out;
    out.window_s = window_s;
    out.windows = ws.size();
    out.iterations = f.iterations;
    const double vs = f.theta[0], vt = f.theta[1];
    out.std_speed_mps = std::sqrt(vs);
    out.std_turn_rate_deg_s = std::sqrt(vt);
    const Eigen::Matrix2d cov = f.info.inverse();
    out.se_speed_mps = std::sqrt(std::max(0.0, cov(0, 0))) / (2 * out.std_speed_mps);
    out.se_turn_rate_deg_s = std::sqrt(std::max(0.0, cov(1, 1))) / (2 * out.std_turn_rate_deg_s);
    size_t inside = 0;
    for (const auto* w : ws)
    {
        const Eigen::Matrix3d S = vs * w->A + vt * w->B + w->V;
        const double e = w->r.dot(S.ldlt().solve(w->r));
        out.mean_nees += e;
        inside += e <= kChi2Dof3P95 ? 1 : 0;
    }
    out.mean_nees /= static_cast<double>(ws.size());
    out.inside_95 = static_cast<double>(inside) / static_cast<double>(ws.size());
    return out;
}

/** Mean NEES and mean squared heading/position residuals and predictions with `f`. */
void compareWith(const std::vector<const Window*>& ws, const MlFit& f, OdometryNoiseFit& out)
{
    const double n = static_cast<double>(ws.size());
    for (const auto* w : ws)
    {
        const Eigen::Matrix3d S = f.theta[0] * w->A + f.theta[1] * w->B + w->V;
        out.mean_nees_joint += w->r.dot(S.ldlt().solve(w->r)) / n;
        out.heading_ms_deg2 += std::pow(mrpt::RAD2DEG(w->r[2]), 2) / n;
        out.heading_model_deg2 += mrpt::RAD2DEG(mrpt::RAD2DEG(S(2, 2))) / n;
        out.position_ms_m2 += w->r.head<2>().squaredNorm() / n;
        out.position_model_m2 += (S(0, 0) + S(1, 1)) / n;
    }
}

/** Ground-truth noise (std_xy [m], std_phi [rad]): the configured values, else
 *  estimated from the track. */
std::pair<double, double> truthStd(const Track& track, const NoiseCalibrationOptions& options)
{
    auto [std_xy, std_phi] = truthNoise(track);
    if (options.truth_std_xy_m >= 0) std_xy = std::max(kMinTruthStd, options.truth_std_xy_m);
    if (options.truth_std_phi_deg >= 0)
        std_phi = std::max(kMinTruthStd, mrpt::DEG2RAD(options.truth_std_phi_deg));
    return {std_xy, std_phi};
}

/** One fit per window length (with the joint fit's NEES and predictions) and the slope of
 *  log mean squared heading residual against log window length. */
void fitPerWindow(const std::vector<std::vector<Window>>& by_length, const MlFit& joint,
                  const WindowInputs& in, const NoiseCalibrationOptions& options, OdometryCalibration& out)
{
    std::vector<double> lx, ly;
    for (size_t i = 0; i < by_length.size(); ++i)
    {
        std::vector<const Window*> ws;
        for (const auto& w : by_length[i]) ws.push_back(&w);
        if (ws.size() < 3) continue;  // two variances need a few windows
        auto fit = describe(ws, fitMl(ws), static_cast<double>(in.steps(options.windows_s[i])) * in.period);
        compareWith(ws, joint, fit);
        if (fit.heading_ms_deg2 > 0)
            lx.push_back(std::log(fit.window_s)), ly.push_back(std::log(fit.heading_ms_deg2));
        out.per_window.push_back(fit);
    }
    if (lx.size() >= 2)
    {
        const double n = static_cast<double>(lx.size());
        double mx = 0, my = 0;
        for (size_t i = 0; i < lx.size(); ++i) mx += lx[i] / n, my += ly[i] / n;
        double sxy = 0, sxx = 0;
        for (size_t i = 0; i < lx.size(); ++i)
            sxy += (lx[i] - mx) * (ly[i] - my), sxx += (lx[i] - mx) * (lx[i] - mx);
        out.heading_growth_exponent = sxx > 0 ? sxy / sxx : std::nan("");
    }
    else
        out.heading_growth_exponent = std::nan("");
}

}  // namespace

namespace detail
{
/** Non-overlapping windows of k truth steps, integrated as the converter does. */
std::vector<Window> makeWindows(const Track& track, size_t k, const OdometryIntegrator& unit_speed,
                                const OdometryIntegrator& unit_turn, double std_xy,
                                double std_phi, std::map<std::string, size_t>& skipped)
{
    std::vector<Window> out;
    for (size_t i = 0; i + k < track.size(); i += k)
    {
        const size_t j = i + k;
        if (!track.clean(i, j))
        {
            skipped["window_truth_break"]++;
            continue;
        }
        const auto &a = track[i], &b = track[j];
        const auto ia = unit_speed.integrate(a.t, b.t);
        if (ia.uncovered_s > 1e-9)
        {
            skipped["window_no_odometry"]++;
            continue;
        }
        const auto ib = unit_turn.integrate(a.t, b.t);
        Window w;
        w.T = b.t - a.t;
        const double c = std::cos(a.phi), s = std::sin(a.phi);
        const double dx = b.x - a.x, dy = b.y - a.y;
        w.truth << c * dx + s * dy, -s * dx + c * dy, mrpt::math::wrapToPi(b.phi - a.phi);
        w.odo << ia.mean.x(), ia.mean.y(), ia.mean.phi();
        w.r = w.truth - w.odo;
        w.r[2] = mrpt::math::wrapToPi(w.r[2]);
        w.A = ia.cov;
        w.B = ib.cov;
        // Noise of the two truth poses: positions (isotropic) and headings; the start
        // heading also rotates the frame the relative position is expressed in.
        const Eigen::Vector3d j_phi0(w.truth[1], -w.truth[0], -1.0);
        w.V = 2 * std_xy * std_xy * Eigen::Vector3d(1, 1, 0).asDiagonal().toDenseMatrix();
        w.V += std_phi * std_phi * (j_phi0 * j_phi0.transpose());
        w.V(2, 2) += std_phi * std_phi;
        out.push_back(w);
    }
    return out;
}
}  // namespace detail

OdometryCalibration calibrateOdometryNoise(
    const std::vector<OdometryIntegrator::ControlSample>& controls,
    const std::vector<StampedPose2D>& truth, const NoiseCalibrationOptions& options,
    const OdometryIntegrator::Options& model)
{
    if (truth.size() < 2) throw std::invalid_argument("calibrateOdometryNoise: fewer than 2 truth poses");
    if (controls.empty()) throw std::invalid_argument("calibrateOdometryNoise: no control sample");
    const Track track(truth, options);
    OdometryCalibration out;
    out.truth_poses = truth.size();
    out.truth_breaks = track.breaks();
    const auto [std_xy, std_phi] = truthStd(track, options);
    out.truth_std_xy_m = std_xy;
    out.truth_std_phi_deg = mrpt::RAD2DEG(std_phi);

    // Unit-variance integrators: the increment covariance is linear in the two variances.
    OI::Options unit = model;
    unit.min_std_xy_m = unit.min_std_phi_deg = 0;
    unit.std_speed_mps = 1, unit.std_turn_rate_deg_s = 0;
    const OI speed(OI::Model::Unicycle, hymm::core::UteParams{}, unit, controls);
    unit.std_speed_mps = 0, unit.std_turn_rate_deg_s = 1;
    const OI turn(OI::Model::Unicycle, hymm::core::UteParams{}, unit, controls);
    const WindowInputs in{track, controls, track.period(), std_xy, std_phi, unit, speed, turn};

    std::vector<std::vector<Window>> by_length;
    for (double len : options.windows_s)
        by_length.push_back(makeWindows(track, in.steps(len), speed, turn, std_xy, std_phi, out.skipped));
    std::vector<const Window*> all;
    for (size_t i = 0; i < by_length.size(); ++i)
        if (options.windows_s[i] >= options.fit_min_window_s - 1e-9)
            for (const auto& w : by_length[i]) all.push_back(&w);
    if (all.size() < 3)
        throw std::invalid_argument(
            "calibrateOdometryNoise: fewer than 3 usable windows of at least fit_min_window_s "
            "(truth breaks, no odometry, or a track shorter than the windows)");
    const MlFit joint = fitMl(all);
    out.joint = describe(all, joint, 0);
    out.fit_min_window_s = options.fit_min_window_s;
    compareWith(all, joint, out.joint);
    fitPerWindow(by_length, joint, in, options, out);

    // Systematic errors (reported only): the command-to-motion delay, then scale and
    // offset of the delayed commands.
    fitCommandBias(in, options, out.bias);
    return out;
}

}  // namespace hymm::datasets
