/**
 * @file NoiseCalibration.cpp
 * @brief Maximum-likelihood control noise over odometry windows and robust
 *        range/bearing residual statistics against a ground-truth track.
 */
#include "hymm/datasets/NoiseCalibration.h"

#include <hymm/core/config_utils.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "hymm/datasets/MrclamImporter.h"
#include "hymm/datasets/import_dataset.h"

namespace hymm::datasets
{
namespace
{
using hymm::io::StampedPose2D;

constexpr double kMadToStd = 1.4826;       // MAD of a Gaussian = 0.6745 std
constexpr double kChi2Dof3P95 = 7.814728;  // chi2 inverse CDF, 3 DOF, 0.95
constexpr double kMinTruthStd = 1e-5;      // floor of the track noise (invertible Sigma)
constexpr int kMaxIterations = 200;

double median(std::vector<double> v)
{
    if (v.empty()) return std::nan("");
    const size_t m = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<long>(m), v.end());
    const double hi = v[m];
    if (v.size() % 2 == 1) return hi;
    return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<long>(m)));
}

/** 1.4826 * median |v - centre|. */
double madStd(const std::vector<double>& v, double centre)
{
    std::vector<double> d;
    d.reserve(v.size());
    for (double x : v) d.push_back(std::abs(x - centre));
    return kMadToStd * median(std::move(d));
}

/**
 * The ground-truth track with its breaks: step s (pose s to s+1) is a break when it is a
 * gap or a jump; clean(i, j) is true when no step between poses i and j is.
 */
class Track
{
   public:
    Track(const std::vector<StampedPose2D>& poses, const NoiseCalibrationOptions& o)
        : poses_(poses), broken_before_(poses.size(), 0)
    {
        for (size_t i = 1; i < poses_.size(); ++i)
        {
            const auto &a = poses_[i - 1], &b = poses_[i];
            if (!(b.t > a.t))
                throw std::invalid_argument("ground truth: time of pose " + std::to_string(i) +
                                            " is not after the previous one");
            const double dt = b.t - a.t;
            const double speed = std::hypot(b.x - a.x, b.y - a.y) / dt;
            const double turn = std::abs(mrpt::math::wrapToPi(b.phi - a.phi)) / dt;
            const bool brk = dt > o.max_gap_s || speed > o.max_speed_mps ||
                             turn > mrpt::DEG2RAD(o.max_turn_rate_deg_s);
            broken_before_[i] = broken_before_[i - 1] + (brk ? 1 : 0);
        }
        breaks_ = poses_.empty() ? 0 : broken_before_.back();
    }

    size_t size() const { return poses_.size(); }
    const StampedPose2D& operator[](size_t i) const { return poses_[i]; }
    size_t breaks() const { return breaks_; }
    bool clean(size_t i, size_t j) const { return broken_before_[j] == broken_before_[i]; }

    /** Median time step [s]. */
    double period() const
    {
        std::vector<double> dt;
        for (size_t i = 1; i < poses_.size(); ++i) dt.push_back(poses_[i].t - poses_[i - 1].t);
        return median(std::move(dt));
    }

    /** Pose interpolated at t; `why` names the reason when there is none. */
    bool interpolate(double t, StampedPose2D& out, std::string& why) const
    {
        if (poses_.empty() || t < poses_.front().t || t > poses_.back().t)
        {
            why = "measurement_outside_truth";
            return false;
        }
        const auto it = std::upper_bound(poses_.begin(), poses_.end(), t,
                                         [](double v, const StampedPose2D& p) { return v < p.t; });
        const size_t j = std::min(static_cast<size_t>(it - poses_.begin()), poses_.size() - 1);
        const size_t i = j == 0 ? 0 : j - 1;
        if (i != j && !clean(i, j))
        {
            why = "measurement_truth_break";
            return false;
        }
        const auto &a = poses_[i], &b = poses_[j];
        const double f = (j == i) ? 0.0 : std::clamp((t - a.t) / (b.t - a.t), 0.0, 1.0);
        out = {t, a.x + f * (b.x - a.x), a.y + f * (b.y - a.y),
               mrpt::math::wrapToPi(a.phi + f * mrpt::math::wrapToPi(b.phi - a.phi))};
        return true;
    }

   private:
    const std::vector<StampedPose2D>& poses_;
    std::vector<size_t> broken_before_;  // breaks among steps 0..i-1 (step s ends at pose s+1)
    size_t breaks_ = 0;
};

/** One odometry window: residual and the model's covariance parts. */
struct Window
{
    double T = 0;            // duration [s]
    Eigen::Vector3d r;       // truth relative pose - integrated increment (x, y, phi)
    Eigen::Matrix3d A, B;    // covariance for unit speed variance [(m/s)^2], turn [(deg/s)^2]
    Eigen::Matrix3d V;       // ground-truth noise of the relative pose
    Eigen::Vector3d truth;   // truth relative pose
    Eigen::Vector3d odo;     // integrated commanded increment
};

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

/** Least squares y = p0 x + p1 T; returns p and the residual std. */
Eigen::Vector2d fitScaleOffset(const std::vector<double>& y, const std::vector<double>& x,
                               const std::vector<double>& T, double& residual_std)
{
    Eigen::MatrixXd M(static_cast<long>(y.size()), 2);
    Eigen::VectorXd Y(static_cast<long>(y.size()));
    for (size_t i = 0; i < y.size(); ++i)
    {
        M(static_cast<long>(i), 0) = x[i];
        M(static_cast<long>(i), 1) = T[i];
        Y[static_cast<long>(i)] = y[i];
    }
    const Eigen::Vector2d p = M.colPivHouseholderQr().solve(Y);
    residual_std = std::sqrt((Y - M * p).squaredNorm() / static_cast<double>(y.size()));
    return p;
}

ResidualStats robustStats(const std::vector<double>& e, double threshold)
{
    ResidualStats s;
    s.used = e.size();
    s.median = median(e);
    s.mad_std = madStd(e, s.median);
    double sum = 0, sum2 = 0;
    size_t n = 0;
    for (double x : e)
    {
        if (std::abs(x - s.median) > threshold * s.mad_std)
        {
            ++s.outliers;
            continue;
        }
        sum += x, sum2 += x * x, ++n;
    }
    if (n > 0)
    {
        s.inlier_mean = sum / static_cast<double>(n);
        s.inlier_std =
            std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - s.inlier_mean * s.inlier_mean));
    }
    s.model_std = std::hypot(s.median, s.mad_std);
    std::vector<double> sorted = e;
    std::sort(sorted.begin(), sorted.end());
    const auto q = [&sorted](double p) {
        return sorted[static_cast<size_t>(std::floor(p * static_cast<double>(sorted.size() - 1)))];
    };
    s.p01 = q(0.01), s.p99 = q(0.99);
    return s;
}

}  // namespace

hymm::core::OptionTable NoiseCalibrationOptions::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.reals("windows_s", windows_s, "s", above(0, 1e6), 1,
            "window lengths of the odometry fit (rounded to whole ground-truth periods)");
    t.real("fit_min_window_s", fit_min_window_s, "s", atLeast(0, 1e6),
           "the joint fit uses the windows from this length on (<= the longest window)");
    t.real("bias_window_s", bias_window_s, "s", above(0, 1e6),
           "window length of the command scale/offset fit");
    t.real("max_gap_s", max_gap_s, "s", above(0, 1e6), "longer ground-truth steps are gaps");
    t.real("max_speed_mps", max_speed_mps, "m/s", above(0, 1000), "faster ground-truth steps are jumps");
    t.real("max_turn_rate_deg_s", max_turn_rate_deg_s, "deg/s", above(0, 1e5), "faster turns are jumps");
    t.real("outlier_threshold", outlier_threshold, "", above(0, 1e6),
           "gross outlier: |e - median| > this x robust std");
    t.real("max_lag_s", max_lag_s, "s", atLeast(0, 1e6), "command-to-motion delays searched");
    t.real("truth_std_xy_m", truth_std_xy_m, "m", atLeast(-1, 100),
           "ground-truth position noise; negative: estimated from the track");
    t.real("truth_std_phi_deg", truth_std_phi_deg, "deg", atLeast(-1, 180),
           "ground-truth heading noise; negative: estimated from the track");
    return t;
}

void NoiseCalibrationOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                 const std::string& section)
{
    table().load(cfg, section);
    if (fit_min_window_s > *std::max_element(windows_s.begin(), windows_s.end()))
        hymm::core::throwConfigError(section, "fit_min_window_s", std::to_string(fit_min_window_s),
                                     "must not exceed the longest of windows_s");
}

void NoiseCalibrationOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                               const std::string& section) const
{
    auto copy = *this;
    copy.table().save(cfg, section);
}

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
    auto [std_xy, std_phi] = truthNoise(track);
    if (options.truth_std_xy_m >= 0) std_xy = std::max(kMinTruthStd, options.truth_std_xy_m);
    if (options.truth_std_phi_deg >= 0)
        std_phi = std::max(kMinTruthStd, mrpt::DEG2RAD(options.truth_std_phi_deg));
    out.truth_std_xy_m = std_xy;
    out.truth_std_phi_deg = mrpt::RAD2DEG(std_phi);

    // Unit-variance integrators: the increment covariance is linear in the two variances.
    using OI = OdometryIntegrator;
    OI::Options unit = model;
    unit.min_std_xy_m = unit.min_std_phi_deg = 0;
    unit.std_speed_mps = 1, unit.std_turn_rate_deg_s = 0;
    const OI speed(OI::Model::Unicycle, hymm::core::UteParams{}, unit, controls);
    unit.std_speed_mps = 0, unit.std_turn_rate_deg_s = 1;
    const OI turn(OI::Model::Unicycle, hymm::core::UteParams{}, unit, controls);

    const double period = track.period();
    const auto steps = [&](double len) {
        return static_cast<size_t>(std::max(1.0, std::round(len / period)));
    };
    std::vector<std::vector<Window>> by_length;
    for (double len : options.windows_s)
        by_length.push_back(makeWindows(track, steps(len), speed, turn, std_xy, std_phi, out.skipped));

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

    std::vector<double> lx, ly;
    for (size_t i = 0; i < by_length.size(); ++i)
    {
        std::vector<const Window*> ws;
        for (const auto& w : by_length[i]) ws.push_back(&w);
        if (ws.size() < 3) continue;  // two variances need a few windows
        auto fit = describe(ws, fitMl(ws), static_cast<double>(steps(options.windows_s[i])) * period);
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

    // Systematic errors (reported only). First the command-to-motion delay: shift the
    // control times, keep the shift with the smallest heading residual.
    const size_t kb = steps(options.bias_window_s);
    out.bias.window_s = static_cast<double>(kb) * period;
    const auto heading_ms = [](const std::vector<Window>& ws) {
        double ms = 0;
        for (const auto& w : ws) ms += w.r[2] * w.r[2] / static_cast<double>(ws.size());
        return ms;
    };
    std::map<std::string, size_t> ignored;
    const auto bw0 = makeWindows(track, kb, speed, turn, std_xy, std_phi, ignored);
    if (bw0.size() < 3) return out;
    const double raw_ms = heading_ms(bw0);
    out.bias.turn_raw_std_deg = mrpt::RAD2DEG(std::sqrt(raw_ms));
    double best = raw_ms;
    const long max_shift = std::lround(options.max_lag_s / period);
    const auto shiftedControls = [&controls, period](long shift) {
        auto c = controls;
        for (auto& s : c) s.t += static_cast<double>(shift) * period;
        return c;
    };
    long best_shift = 0;
    for (long shift = -max_shift; shift <= max_shift; ++shift)
    {
        if (shift == 0) continue;
        const OI turn_s(OI::Model::Unicycle, hymm::core::UteParams{}, unit, shiftedControls(shift));
        const auto sw = makeWindows(track, kb, turn_s, turn_s, std_xy, std_phi, ignored);
        const double ms = heading_ms(sw);
        if (sw.size() >= bw0.size() / 2 && ms < best) best = ms, best_shift = shift;
    }
    out.bias.lag_s = static_cast<double>(best_shift) * period;
    out.bias.lag_heading_std_deg = mrpt::RAD2DEG(std::sqrt(best));

    // Then scale and offset of the delayed commands, so that the delay does not bias the
    // regression towards zero.
    const OI delayed(OI::Model::Unicycle, hymm::core::UteParams{}, unit, shiftedControls(best_shift));
    const auto bw = makeWindows(track, kb, delayed, delayed, std_xy, std_phi, ignored);
    out.bias.windows = bw.size();
    std::vector<double> yd, xd, yh, xh, T;
    for (const auto& w : bw)
    {
        // Distance along the commanded chord (a projection: zero-mean noise stays
        // zero-mean, unlike the length of the true chord).
        const double d = w.odo.head<2>().norm();
        yd.push_back(d > 1e-9 ? w.truth.head<2>().dot(w.odo.head<2>()) / d : 0.0);
        xd.push_back(d);
        yh.push_back(w.truth[2]), xh.push_back(w.odo[2]), T.push_back(w.T);
    }
    double sd = 0, sh = 0;
    const Eigen::Vector2d pd = fitScaleOffset(yd, xd, T, sd);
    const Eigen::Vector2d ph = fitScaleOffset(yh, xh, T, sh);
    out.bias.speed_scale = pd[0], out.bias.speed_offset_mps = pd[1];
    out.bias.turn_scale = ph[0], out.bias.turn_offset_deg_s = mrpt::RAD2DEG(ph[1]);
    out.bias.turn_residual_std_deg = mrpt::RAD2DEG(sh);
    return out;
}

MeasurementCalibration calibrateMeasurementNoise(
    const std::vector<LandmarkMeasurement>& measurements, const std::vector<StampedPose2D>& truth,
    const std::vector<hymm::io::LandmarkRecord>& landmarks, const NoiseCalibrationOptions& options)
{
    const Track track(truth, options);
    std::map<long, Eigen::Vector2d> lm;
    for (const auto& l : landmarks) lm[l.id] = Eigen::Vector2d(l.x, l.y);
    MeasurementCalibration out;
    std::vector<double> er, eb, range;
    std::vector<long> ids;
    std::vector<StampedPose2D> poses;
    for (const auto& m : measurements)
    {
        const auto it = lm.find(m.id);
        if (it == lm.end())
        {
            out.skipped["measurement_unknown_landmark"]++;
            continue;
        }
        StampedPose2D p;
        std::string why;
        if (!track.interpolate(m.t, p, why))
        {
            out.skipped[why]++;
            continue;
        }
        const Eigen::Vector2d d = it->second - Eigen::Vector2d(p.x, p.y);
        er.push_back(m.range - d.norm());
        eb.push_back(mrpt::RAD2DEG(mrpt::math::wrapToPi(m.bearing - (std::atan2(d.y(), d.x()) - p.phi))));
        range.push_back(m.range);
        ids.push_back(m.id);
        poses.push_back(p);
    }
    if (er.empty())
        throw std::invalid_argument(
            "calibrateMeasurementNoise: no measurement of a known landmark inside the ground truth");
    out.range = robustStats(er, options.outlier_threshold);
    out.bearing = robustStats(eb, options.outlier_threshold);
    for (size_t i = 0; i < er.size(); ++i)
    {
        auto& c = out.outliers_by_landmark[ids[i]];
        ++c.first;
        const bool out_r = std::abs(er[i] - out.range.median) >
                           options.outlier_threshold * out.range.mad_std;
        const bool out_b = std::abs(eb[i] - out.bearing.median) >
                           options.outlier_threshold * out.bearing.mad_std;
        c.second += (out_r || out_b) ? 1 : 0;
    }
    // Which surveyed landmark explains each label's measurements best.
    std::map<long, std::map<long, size_t>> votes;
    for (size_t i = 0; i < er.size(); ++i)
    {
        const double r_meas = er[i] + (lm[ids[i]] - Eigen::Vector2d(poses[i].x, poses[i].y)).norm();
        const double b_meas = mrpt::DEG2RAD(eb[i]) +
                              std::atan2(lm[ids[i]].y() - poses[i].y, lm[ids[i]].x() - poses[i].x) -
                              poses[i].phi;
        long best = -1;
        double best_cost = std::numeric_limits<double>::infinity();
        for (const auto& [id, pos] : lm)
        {
            const Eigen::Vector2d d = pos - Eigen::Vector2d(poses[i].x, poses[i].y);
            const double dr = (r_meas - d.norm()) / out.range.mad_std;
            const double db = mrpt::RAD2DEG(mrpt::math::wrapToPi(
                                  b_meas - (std::atan2(d.y(), d.x()) - poses[i].phi))) /
                              out.bearing.mad_std;
            if (dr * dr + db * db < best_cost) best_cost = dr * dr + db * db, best = id;
        }
        votes[ids[i]][best]++;
    }
    for (const auto& [label, v] : votes)
    {
        size_t total = 0;
        std::pair<long, size_t> top{-1, 0};
        for (const auto& [id, n] : v)
        {
            total += n;
            if (n > top.second) top = {id, n};
        }
        out.best_fit_landmark[label] = {top.first, static_cast<double>(top.second) /
                                                       static_cast<double>(total)};
    }
    const double inf = std::numeric_limits<double>::infinity();
    double lo = 0;
    for (double hi : {1.5, 3.0, 4.5, inf})
    {
        std::vector<double> e;
        for (size_t i = 0; i < er.size(); ++i)
            if (range[i] >= lo && range[i] < hi) e.push_back(er[i]);
        if (!e.empty()) out.range_std_by_range[hi] = {e.size(), madStd(e, median(e))};
        lo = hi;
    }
    return out;
}

NoiseCalibrationResult calibrateMrclam(const std::vector<std::string>& inputs, int robot,
                                       const std::string& config_file)
{
    MrclamImporter::Options mo;
    NoiseCalibrationOptions co;
    if (!config_file.empty())
    {
        const auto cfg = hymm::core::openConfigFile(config_file);
        mo.loadFromConfigFile(*cfg, "MrclamImporter");
        co.loadFromConfigFile(*cfg, "NoiseCalibration");
    }
    if (robot < 1 || robot > mo.num_robots)
        throw std::invalid_argument("calibrateMrclam: robot " + std::to_string(robot) +
                                    " is not in 1.." + std::to_string(mo.num_robots));
    mo.robot = robot;
    const auto in = MrclamImporter::findInputs(inputs, robot);
    if (in.groundtruth.empty() || in.landmarks.empty())
        throw std::runtime_error("calibrateMrclam: Robot" + std::to_string(robot) +
                                 "_Groundtruth.dat and Landmark_Groundtruth.dat are required");
    NoiseCalibrationResult res;
    res.reading.format = "mrclam";
    const auto dir = std::filesystem::path(in.odometry).parent_path();
    res.source = (dir.filename().empty() ? dir.string() : dir.filename().string()) + " robot " +
                 std::to_string(robot);
    const MrclamImporter imp(mo);
    const auto controls = imp.readOdometry(in.odometry, res.reading);
    res.reading.odometry_samples = controls.size();
    const auto truth = imp.readGroundTruth(in.groundtruth, res.reading);
    res.reading.ground_truth_poses = truth.size();
    const auto lms = MrclamImporter::readLandmarks(in.landmarks, res.reading);
    res.reading.landmarks = lms.size();
    std::vector<LandmarkMeasurement> meas;
    for (const auto& o : imp.readMeasurements(in.measurements,
                                              imp.barcodeMap(in.barcodes, res.reading),
                                              res.reading))
    {
        const auto& br = dynamic_cast<const mrpt::obs::CObservationBearingRange&>(*o);
        for (const auto& m : br.sensedData)
            meas.push_back({mrpt::Clock::toDouble(br.timestamp), m.landmarkID, m.range, m.yaw});
    }
    res.odometry = calibrateOdometryNoise(controls, truth, co, mo.odometry);
    res.measurements = calibrateMeasurementNoise(meas, truth, lms, co);
    return res;
}

std::string NoiseCalibrationResult::iniLines() const
{
    std::ostringstream s;
    s << std::setprecision(3);
    s << "std_speed_mps = " << odometry.joint.std_speed_mps << "\n"
      << "std_turn_rate_deg_s = " << odometry.joint.std_turn_rate_deg_s << "\n"
      << "std_range_m = " << measurements.range.model_std << "\n"
      << "std_bearing_deg = " << measurements.bearing.model_std << "\n";
    return s.str();
}

std::string NoiseCalibrationResult::toString() const
{
    std::ostringstream s;
    const auto& o = odometry;
    const auto counts = [&s](const std::map<std::string, size_t>& m) {
        if (m.empty()) s << " none";
        for (const auto& [k, v] : m) s << " " << k << "=" << v;
        s << "\n";
    };
    s << std::fixed;
    s << "noise calibration on " << source << "\n"
      << "reading: " << reading.odometry_samples << " control samples, "
      << reading.ground_truth_poses << " ground-truth poses, " << reading.measurements
      << " measurements, " << reading.landmarks << " landmarks\n  skipped:";
    counts(reading.skipped);
    s << "  repaired:";
    counts(reading.repaired);
    s << std::setprecision(5) << "ground truth: " << o.truth_breaks << " breaks (gaps/jumps) in "
      << o.truth_poses << " poses; noise from second differences: " << o.truth_std_xy_m
      << " m, " << o.truth_std_phi_deg << " deg\n";
    s << "odometry windows skipped:";
    counts(o.skipped);
    s << "odometry noise, maximum likelihood per window length (per-sample model):\n"
      << "  window_s windows std_speed_mps (se) std_turn_rate_deg_s (se) mean_NEES in95 | "
         "joint: mean_NEES heading_ms/model_deg2 position_ms/model_m2\n";
    const auto row = [&s](const OdometryNoiseFit& f) {
        s << std::setprecision(3) << "  " << std::setw(8) << f.window_s << std::setw(8)
          << f.windows << std::setprecision(4) << std::setw(10) << f.std_speed_mps << " ("
          << f.se_speed_mps << ")" << std::setw(10) << f.std_turn_rate_deg_s << " ("
          << f.se_turn_rate_deg_s << ")" << std::setprecision(2) << std::setw(8) << f.mean_nees
          << std::setw(6) << 100 * f.inside_95 << "% | " << f.mean_nees_joint << " "
          << std::setprecision(4) << f.heading_ms_deg2 << "/" << f.heading_model_deg2 << " "
          << std::setprecision(6) << f.position_ms_m2 << "/" << f.position_model_m2 << "\n";
    };
    for (const auto& f : o.per_window) row(f);
    s << "  joint (windows from " << std::setprecision(3) << o.fit_min_window_s
      << " s on: the values for the config):\n";
    row(o.joint);
    s << std::setprecision(2) << "heading growth exponent (log mean squared heading residual vs "
      << "log window): " << o.heading_growth_exponent
      << " (1: per-sample random walk, 2: systematic)\n";
    s << std::setprecision(4) << "command-to-motion delay: " << o.bias.lag_s
      << " s (heading residual RMS over " << o.bias.window_s << " s windows "
      << o.bias.turn_raw_std_deg << " deg -> " << o.bias.lag_heading_std_deg
      << " deg with the controls delayed by it)\n"
      << "delayed commands, scale/offset over " << o.bias.windows << " windows: distance = "
      << o.bias.speed_scale << " * commanded + " << o.bias.speed_offset_mps
      << " m/s * T; heading = " << o.bias.turn_scale << " * commanded + "
      << o.bias.turn_offset_deg_s << " deg/s * T (heading residual RMS -> "
      << o.bias.turn_residual_std_deg << " deg after the fit)\n";
    const auto& m = measurements;
    s << "measurements skipped:";
    counts(m.skipped);
    const auto stats = [&s](const char* what, const ResidualStats& r, const char* unit) {
        s << std::setprecision(4) << what << ": " << r.used << " residuals, median " << r.median
          << " " << unit << ", MAD std " << r.mad_std << " " << unit << ", " << r.outliers
          << " gross outliers; 1%/99% quantiles " << r.p01 << "/" << r.p99 << " " << unit
          << "; inliers mean " << r.inlier_mean << " std " << r.inlier_std
          << "; zero-mean std sqrt(median^2+MAD^2) = " << r.model_std << " " << unit << "\n";
    };
    stats("range", m.range, "m");
    stats("bearing", m.bearing, "deg");
    s << "range MAD std by measured range:";
    double lo = 0;
    for (const auto& [hi, v] : m.range_std_by_range)
    {
        s << " [" << std::setprecision(1) << lo << "," << hi << ") m: " << std::setprecision(4)
          << v.second << " m (" << v.first << ");";
        lo = hi;
    }
    s << "\ngross outliers (range or bearing) by landmark id:";
    for (const auto& [id, c] : m.outliers_by_landmark)
        s << " " << id << ": " << c.second << "/" << c.first << ";";
    s << "\nlabels whose measurements fit another surveyed landmark best:";
    size_t mislabelled = 0;
    for (const auto& [label, best] : m.best_fit_landmark)
        if (best.first != label)
            s << " " << label << " -> " << best.first << " (" << std::setprecision(0)
              << 100 * best.second << "% of its measurements);", ++mislabelled;
    if (mislabelled == 0) s << " none";
    s << "\n";
    return s.str();
}

}  // namespace hymm::datasets
