/**
 * @file NoiseCalibrationBias.cpp
 * @brief Systematic errors of the odometry commands against a ground-truth track: the
 *        command-to-motion delay, then scale and offset of the delayed commands.
 */
#include <mrpt/core/bits_math.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "noise_calibration_track.h"

namespace hymm::datasets::detail
{
namespace
{
using OI = OdometryIntegrator;

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

double headingMeanSquare(const std::vector<Window>& ws)
{
    double ms = 0;
    for (const auto& w : ws) ms += w.r[2] * w.r[2] / static_cast<double>(ws.size());
    return ms;
}

/** The controls with their times shifted by `shift` ground-truth periods. */
std::vector<OI::ControlSample> shiftedControls(const WindowInputs& in, long shift)
{
    auto c = in.controls;
    for (auto& s : c) s.t += static_cast<double>(shift) * in.period;
    return c;
}

/** The command-to-motion delay: shifts the control times, keeps the shift (in periods)
 *  with the smallest heading residual over windows of `kb` steps. */
long fitDelay(const WindowInputs& in, size_t kb, const std::vector<Window>& bw0,
              const NoiseCalibrationOptions& options, OdometryBiasFit& bias)
{
    std::map<std::string, size_t> ignored;
    const double raw_ms = headingMeanSquare(bw0);
    bias.turn_raw_std_deg = mrpt::RAD2DEG(std::sqrt(raw_ms));
    double best = raw_ms;
    const long max_shift = std::lround(options.max_lag_s / in.period);
    long best_shift = 0;
    for (long shift = -max_shift; shift <= max_shift; ++shift)
    {
        if (shift == 0) continue;
        const OI turn_s(OI::Model::Unicycle, hymm::core::UteParams{}, in.unit, shiftedControls(in, shift));
        const auto sw = makeWindows(in.track, kb, turn_s, turn_s, in.std_xy, in.std_phi, ignored);
        const double ms = headingMeanSquare(sw);
        if (sw.size() >= bw0.size() / 2 && ms < best) best = ms, best_shift = shift;
    }
    bias.lag_s = static_cast<double>(best_shift) * in.period;
    bias.lag_heading_std_deg = mrpt::RAD2DEG(std::sqrt(best));
    return best_shift;
}

/** Scale and offset of the commands delayed by `shift` periods, so that the delay does
 *  not bias the regression towards zero. */
void fitScaleAndOffset(const WindowInputs& in, size_t kb, long shift, OdometryBiasFit& bias)
{
    std::map<std::string, size_t> ignored;
    const OI delayed(OI::Model::Unicycle, hymm::core::UteParams{}, in.unit, shiftedControls(in, shift));
    const auto bw = makeWindows(in.track, kb, delayed, delayed, in.std_xy, in.std_phi, ignored);
    bias.windows = bw.size();
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
    bias.speed_scale = pd[0], bias.speed_offset_mps = pd[1];
    bias.turn_scale = ph[0], bias.turn_offset_deg_s = mrpt::RAD2DEG(ph[1]);
    bias.turn_residual_std_deg = mrpt::RAD2DEG(sh);
}
}  // namespace

void fitCommandBias(const WindowInputs& in, const NoiseCalibrationOptions& options, OdometryBiasFit& bias)
{
    const size_t kb = in.steps(options.bias_window_s);
    bias.window_s = static_cast<double>(kb) * in.period;
    std::map<std::string, size_t> ignored;
    const auto bw0 = makeWindows(in.track, kb, in.speed, in.turn, in.std_xy, in.std_phi, ignored);
    if (bw0.size() < 3) return;
    const long shift = fitDelay(in, kb, bw0, options, bias);
    fitScaleAndOffset(in, kb, shift, bias);
}

}  // namespace hymm::datasets::detail
