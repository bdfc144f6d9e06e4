#include "hymm/datasets/OdometryIntegrator.h"

#include <hymm/core/config_utils.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "hymm/datasets/ImportSummary.h"

namespace hymm::datasets
{
namespace
{
// The UTE model's Eq. A.3 divides by (1 - tan(alpha) H / L); uteAxleSpeed refuses
// steering that makes this ratio reach 0.99. Samples beyond it are logging errors.
constexpr double kMaxSteeringRatio = 0.99;
}  // namespace

hymm::core::OptionTable OdometryIntegrator::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("std_speed_mps", std_speed_mps, "m/s", atLeast(0, 100), "std of one speed sample");
    t.real("std_steering_deg", std_steering_deg, "deg", atLeast(0, 90),
           "std of one steering sample (UTE model)");
    t.real("std_turn_rate_deg_s", std_turn_rate_deg_s, "deg/s", atLeast(0, 3600),
           "std of one turn-rate sample (unicycle)");
    t.real("max_hold_s", max_hold_s, "s", above(0, 3600), "longest time a sample is held");
    t.real("min_std_xy_m", min_std_xy_m, "m", above(0, 100), "floor added to each increment, x and y");
    t.real("min_std_phi_deg", min_std_phi_deg, "deg", above(0, 180),
           "floor added to each increment, heading");
    return t;
}

const std::vector<std::string>& OdometryIntegrator::Options::keys()
{
    static const std::vector<std::string> k = Options().table().names();
    return k;
}

void OdometryIntegrator::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    table().load(cfg, section);
}

void OdometryIntegrator::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    auto copy = *this;
    copy.table().save(cfg, section);
}

OdometryIntegrator::OdometryIntegrator(Model model, const hymm::core::UteParams& ute,
                                       const Options& options,
                                       std::vector<ControlSample> samples)
    : model_(model), ute_(ute), options_(options), samples_(std::move(samples))
{
    for (size_t i = 0; i < samples_.size(); ++i)
    {
        const auto& s = samples_[i];
        if (!std::isfinite(s.t) || !std::isfinite(s.u0) || !std::isfinite(s.u1))
            throw std::invalid_argument("OdometryIntegrator: sample " + std::to_string(i) +
                                        " is not finite");
        if (i > 0 && !(s.t > samples_[i - 1].t))
            throw std::invalid_argument("OdometryIntegrator: sample " + std::to_string(i) +
                                        " time is not increasing");
    }
}

std::vector<OdometryIntegrator::ControlSample> OdometryIntegrator::sanitize(
    const std::vector<ControlSample>& raw, Model model, const hymm::core::UteParams& ute,
    ImportSummary& summary)
{
    std::vector<ControlSample> out;
    out.reserve(raw.size());
    for (const auto& s : raw)
    {
        if (!std::isfinite(s.t) || !std::isfinite(s.u0) || !std::isfinite(s.u1))
            summary.skip("odometry_nan");
        else if (!out.empty() && !(s.t > out.back().t))
            summary.skip("odometry_non_monotonic");
        else if (model == Model::Ute &&
                 std::abs(std::tan(s.u1)) * std::abs(ute.H) / ute.L >= kMaxSteeringRatio)
            summary.skip("odometry_steering_out_of_range");
        else
            out.push_back(s);
    }
    return out;
}

Eigen::Vector3d OdometryIntegrator::step(const ControlSample& s, double dt,
                                         Eigen::Matrix3d& cov) const
{
    Eigen::Matrix<double, 3, 2> J;
    Eigen::Vector3d d;
    Eigen::Vector2d q_std(options_.std_speed_mps, 0.0);
    if (model_ == Model::Ute)
    {
        d = hymm::core::uteIncrement(Eigen::Vector2d(s.u0, s.u1), dt, ute_, &J);
        q_std[1] = mrpt::DEG2RAD(options_.std_steering_deg);
    }
    else
    {  // arc step: translation along the mid-step heading
        const double h = 0.5 * s.u1 * dt, c = std::cos(h), sn = std::sin(h);
        d << s.u0 * dt * c, s.u0 * dt * sn, s.u1 * dt;
        J << dt * c, -s.u0 * dt * sn * 0.5 * dt,  //
            dt * sn, s.u0 * dt * c * 0.5 * dt,    //
            0.0, dt;
        q_std[1] = mrpt::DEG2RAD(options_.std_turn_rate_deg_s);
    }
    const Eigen::Matrix2d Q = q_std.cwiseAbs2().asDiagonal();
    cov = J * Q * J.transpose();
    return d;
}

OdometryIntegrator::Increment OdometryIntegrator::integrate(double t0, double t1) const
{
    if (!(t1 >= t0))
        throw std::invalid_argument("OdometryIntegrator::integrate: t1 < t0 (" +
                                    std::to_string(t0) + " > " + std::to_string(t1) + ")");
    Increment inc;
    Eigen::Vector3d D = Eigen::Vector3d::Zero();
    Eigen::Matrix3d P = Eigen::Matrix3d::Zero();

    // Index of the sample active at t0 (-1: before the first sample).
    const auto it = std::upper_bound(samples_.begin(), samples_.end(), t0,
                                     [](double t, const ControlSample& s) { return t < s.t; });
    auto k = static_cast<long>(it - samples_.begin()) - 1;
    const auto n = static_cast<long>(samples_.size());
    double t = t0;
    while (t < t1)
    {
        const double next_t =
            (k + 1 < n) ? samples_[k + 1].t : std::numeric_limits<double>::infinity();
        const double seg_end = std::min(t1, next_t);
        double hold_end = t;
        if (k >= 0) hold_end = std::max(t, std::min(seg_end, samples_[k].t + options_.max_hold_s));
        if (hold_end > t)
        {
            Eigen::Matrix3d Qd;
            const Eigen::Vector3d d = step(samples_[k], hold_end - t, Qd);
            // Compose D (+) d with first-order covariance propagation.
            const double c = std::cos(D[2]), s = std::sin(D[2]);
            Eigen::Matrix3d J1 = Eigen::Matrix3d::Identity();
            J1(0, 2) = -s * d[0] - c * d[1];
            J1(1, 2) = c * d[0] - s * d[1];
            Eigen::Matrix3d J2 = Eigen::Matrix3d::Identity();
            J2.topLeftCorner<2, 2>() << c, -s, s, c;
            P = J1 * P * J1.transpose() + J2 * Qd * J2.transpose();
            D = Eigen::Vector3d(D[0] + c * d[0] - s * d[1], D[1] + s * d[0] + c * d[1],
                                mrpt::math::wrapToPi(D[2] + d[2]));
            ++inc.steps;
        }
        inc.uncovered_s += seg_end - hold_end;
        t = seg_end;
        ++k;
    }
    const double sxy = options_.min_std_xy_m, sphi = mrpt::DEG2RAD(options_.min_std_phi_deg);
    P += Eigen::Vector3d(sxy * sxy, sxy * sxy, sphi * sphi).asDiagonal();
    inc.mean = mrpt::poses::CPose2D(D[0], D[1], D[2]);
    inc.cov = 0.5 * (P + P.transpose());
    return inc;
}

}  // namespace hymm::datasets
