// The ground-truth track of the noise calibration with its breaks, the robust statistics
// both calibrations use, and the odometry windows (private to hymm::datasets).
#pragma once

#include <hymm/datasets/NoiseCalibration.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace hymm::datasets::detail
{
using hymm::io::StampedPose2D;

constexpr double kMadToStd = 1.4826;   // MAD of a Gaussian = 0.6745 std
constexpr double kMinTruthStd = 1e-5;  // floor of the track noise (invertible Sigma)

inline double median(std::vector<double> v)
{
    if (v.empty()) return std::nan("");
    const size_t m = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<long>(m), v.end());
    const double hi = v[m];
    if (v.size() % 2 == 1) return hi;
    return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<long>(m)));
}

/** 1.4826 * median |v - centre|. */
inline double madStd(const std::vector<double>& v, double centre)
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

/** What the window fits share: the track, its median period, its noise and the
 *  unit-variance integrators (the increment covariance is linear in the two variances). */
struct WindowInputs
{
    const Track& track;
    const std::vector<OdometryIntegrator::ControlSample>& controls;
    double period;
    double std_xy, std_phi;
    OdometryIntegrator::Options unit;  // unit turn-rate variance, no speed noise (unit speed: `speed`)
    const OdometryIntegrator& speed;
    const OdometryIntegrator& turn;

    /** Whole ground-truth periods in a window of `len` seconds (at least one). */
    size_t steps(double len) const { return static_cast<size_t>(std::max(1.0, std::round(len / period))); }
};

/** Non-overlapping windows of k truth steps, integrated as the converter does;
 *  `skipped` counts the windows left out, by reason. */
std::vector<Window> makeWindows(const Track& track, size_t k, const OdometryIntegrator& unit_speed,
                                const OdometryIntegrator& unit_turn, double std_xy,
                                double std_phi, std::map<std::string, size_t>& skipped);

/** Systematic errors of the commands (reported only): the command-to-motion delay, then
 *  scale and offset of the delayed commands, over windows of bias_window_s. */
void fitCommandBias(const WindowInputs& in, const NoiseCalibrationOptions& options, OdometryBiasFit& bias);

}  // namespace hymm::datasets::detail
