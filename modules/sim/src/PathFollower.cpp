#include "hymm/sim/PathFollower.h"

#include <hymm/core/config_utils.h>

#include <algorithm>
#include <cmath>

#include "config_text.h"

namespace hymm::sim
{
namespace
{
// Window of the progress search around the previous progress [m]: the vehicle moves a
// few centimetres per step, and a narrow window never jumps to a nearby part of the loop.
constexpr double kSearchBack = 2.0;
constexpr double kSearchAhead = 5.0;
}  // namespace

hymm::core::OptionTable PathFollower::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.custom(detail::groupsKey(
        "waypoints", "m", 2, 0, 1e6, "the loop's corners `x y x y ...` (1 point: parked; else at least 3)",
        [this](const std::vector<double>& v, const std::string& s, const std::string& raw) {
            if (v.size() == 4)
                throwConfigError(s, "waypoints", raw, "give 1 point (parked) or at least 3 (a loop)");
            waypoints.clear();
            for (size_t i = 0; i < v.size(); i += 2) waypoints.emplace_back(v[i], v[i + 1]);
        },
        [this]() {
            std::vector<double> v;
            for (const auto& p : waypoints) v.insert(v.end(), {p.x(), p.y()});
            return v;
        }));
    t.real("corner_radius_m", corner_radius_m, "m", between(0, 1e4), "corners rounded with arcs of this radius");
    t.real("lookahead_m", lookahead_m, "m", above(0, 1e4), "pure-pursuit look-ahead distance");
    return t;
}

void PathFollower::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                               const std::string& s)
{
    table().load(cfg, s);
    if (waypoints.empty())
        hymm::core::throwConfigError(s, "waypoints", hymm::core::readString(cfg, s, "waypoints", ""),
                                     "required: the loop's corners x y x y ...");
}

void PathFollower::Options::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                             const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

PathFollower::PathFollower(const Options& options, const hymm::core::UteParams& ute,
                           double max_steering)
    : options_(options), ute_(ute), max_steering_(max_steering)
{
    if (options_.waypoints.size() > 1) path_.emplace(options_.waypoints, options_.corner_radius_m);
}

Eigen::Vector3d PathFollower::startPose() const
{
    if (!path_) return {options_.waypoints.at(0).x(), options_.waypoints.at(0).y(), 0.0};
    const Vec2 p = path_->pointAt(0);
    return {p.x(), p.y(), path_->headingAt(0)};
}

double PathFollower::steering(const Eigen::Vector3d& pose)
{
    if (!path_) return 0.0;
    const Vec2 p(pose[0], pose[1]);
    progress_ = path_->project(p, progress_, kSearchBack, kSearchAhead);
    const Vec2 goal = path_->pointAt(progress_ + options_.lookahead_m);

    // Goal in the rear-axle frame: the axle centre is (a, b) behind the tracked point.
    const double c = std::cos(pose[2]), s = std::sin(pose[2]);
    const Vec2 axle = p - Vec2(c * ute_.a - s * ute_.b, s * ute_.a + c * ute_.b);
    const Vec2 d = goal - axle;
    const double gx = c * d.x() + s * d.y(), gy = -s * d.x() + c * d.y();

    const double num = 2 * ute_.L * (gy - ute_.b);
    const double den = gx * gx + gy * gy - ute_.a * ute_.a - ute_.b * ute_.b;
    double alpha = 0;
    if (den > 1e-9)
        alpha = std::atan(num / den);
    else if (num != 0)  // goal no farther from the axle than P: turn as hard as allowed
        alpha = std::copysign(max_steering_, num);
    return std::clamp(alpha, -max_steering_, max_steering_);
}

}  // namespace hymm::sim
