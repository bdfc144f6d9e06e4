/**
 * @file noise_calibration_runs.h
 * @brief Synthetic odometry runs for the noise calibration tests: commands, true controls =
 *        commands + known per-sample noise (or systematic errors), and the true path
 *        integrated from them.
 */
#pragma once

#include <hymm/datasets/NoiseCalibration.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <random>
#include <vector>

namespace hymm::test
{
using hymm::io::StampedPose2D;
using Control = hymm::datasets::OdometryIntegrator::ControlSample;

constexpr double kDt = 0.02;

struct SyntheticRun
{
    std::vector<Control> commands;
    std::vector<StampedPose2D> truth;  // pose at each command time (before that sample)
};

/**
 * Piecewise-constant commands (segments of 1-6 s) at 50 Hz; the robot executes
 * speed_scale * v + noise and turn_scale * omega + noise of the command `delay`
 * samples earlier, each sample an arc step as the converter's unicycle model.
 */
inline SyntheticRun makeRun(double seconds, double std_v, double std_w_deg, unsigned seed,
                     double speed_scale = 1, double turn_scale = 1, int delay = 0)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> seg_len(50, 300), pick(0, 2);
    std::normal_distribution<double> n01(0, 1);
    SyntheticRun r;
    const auto n = static_cast<size_t>(seconds / kDt);
    double v = 0, w = 0;
    int left = 0;
    for (size_t i = 0; i < n; ++i)
    {
        if (left-- <= 0)
        {
            left = seg_len(rng);
            v = 0.1 * pick(rng);
            w = 0.4 * (pick(rng) - 1);
        }
        r.commands.push_back({static_cast<double>(i) * kDt, v, w});
    }
    double x = 0, y = 0, phi = 0;
    for (size_t i = 0; i < n; ++i)
    {
        r.truth.push_back({static_cast<double>(i) * kDt, x, y, phi});
        const Control& c = r.commands[i >= static_cast<size_t>(delay) ? i - delay : 0];
        const double cv = i >= static_cast<size_t>(delay) ? c.u0 : 0.0;
        const double cw = i >= static_cast<size_t>(delay) ? c.u1 : 0.0;
        const double tv = speed_scale * cv + std_v * n01(rng);
        const double tw = turn_scale * cw + mrpt::DEG2RAD(std_w_deg) * n01(rng);
        const double h = phi + 0.5 * tw * kDt;
        x += tv * kDt * std::cos(h);
        y += tv * kDt * std::sin(h);
        phi = mrpt::math::wrapToPi(phi + tw * kDt);
    }
    return r;
}

}  // namespace hymm::test
