#include "hymm/eval/TrajectoryEvaluator.h"

#include <hymm/core/config_utils.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace hymm::eval
{
namespace
{
using io::StampedPose2D;
using mrpt::math::wrapToPi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::optional<StampedPose2D> nearestInTime(
    const std::vector<StampedPose2D>& sorted, double t, double tol)
{
    auto it = std::lower_bound(sorted.begin(), sorted.end(), t,
                               [](const StampedPose2D& p, double tt) { return p.t < tt; });
    const StampedPose2D* best = nullptr;
    if (it != sorted.end()) best = &*it;
    if (it != sorted.begin() && (!best || t - std::prev(it)->t < best->t - t)) best = &*std::prev(it);
    if (!best || std::abs(best->t - t) > tol) return std::nullopt;
    return *best;
}

std::optional<StampedPose2D> interpolateInTime(
    const std::vector<StampedPose2D>& sorted, double t, double max_gap)
{
    auto it = std::lower_bound(sorted.begin(), sorted.end(), t,
                               [](const StampedPose2D& p, double tt) { return p.t < tt; });
    if (it == sorted.end()) return std::nullopt;
    if (it->t == t) return *it;
    if (it == sorted.begin()) return std::nullopt;
    const StampedPose2D& a = *std::prev(it);
    const StampedPose2D& b = *it;
    if (b.t - a.t > max_gap) return std::nullopt;
    const double u = (t - a.t) / (b.t - a.t);
    return StampedPose2D{t, a.x + u * (b.x - a.x), a.y + u * (b.y - a.y),
                         wrapToPi(a.phi + u * wrapToPi(b.phi - a.phi))};
}

struct Pair
{
    StampedPose2D est, truth;
};

std::vector<Pair> associate(
    const std::vector<StampedPose2D>& estimate, const std::vector<StampedPose2D>& truth,
    const TrajectoryEvaluator::Options& o)
{
    std::vector<Pair> pairs;
    if (o.association == TrajectoryEvaluator::Association::Index)
    {
        for (size_t i = 0; i < std::min(estimate.size(), truth.size()); ++i)
            pairs.push_back({estimate[i], truth[i]});
        return pairs;
    }
    std::vector<StampedPose2D> sorted = truth;
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const StampedPose2D& a, const StampedPose2D& b) { return a.t < b.t; });
    for (const auto& e : estimate)
    {
        const auto g = o.association == TrajectoryEvaluator::Association::Nearest
                           ? nearestInTime(sorted, e.t, o.time_tolerance)
                           : interpolateInTime(sorted, e.t, o.time_tolerance);
        if (g) pairs.push_back({e, *g});
    }
    return pairs;
}
}  // namespace

double TrajectoryEvaluator::PoseError::position() const { return std::hypot(dx, dy); }

std::string TrajectoryEvaluator::associationName(Association a)
{
    switch (a)
    {
        case Association::Nearest: return "nearest";
        case Association::Interpolate: return "interpolate";
        case Association::Index: return "index";
    }
    return "?";
}

TrajectoryEvaluator::Association TrajectoryEvaluator::parseAssociation(const std::string& name)
{
    if (name == "nearest") return Association::Nearest;
    if (name == "interpolate") return Association::Interpolate;
    if (name == "index") return Association::Index;
    throw std::invalid_argument("trajectory association '" + name +
                                "' must be one of nearest, interpolate, index");
}

hymm::core::OptionTable TrajectoryEvaluator::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.choice("association", association,
             {{"nearest", Association::Nearest},
              {"interpolate", Association::Interpolate},
              {"index", Association::Index}},
             "pair estimate and ground truth by nearest time, by interpolating the truth, or by index");
    t.real("time_tolerance", time_tolerance, "s", above(0, 1e6),
           "largest time difference of a nearest/interpolated match");
    t.flag("align", align, "fit an SE(2) transform before computing errors");
    t.real("align_fit_distance", align_fit_distance, "m", atLeast(0, 1e9),
           "with align: 0 fits on every matched pose; > 0 only on the poses within this many metres travelled");
    return t;
}

void TrajectoryEvaluator::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void TrajectoryEvaluator::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void TrajectoryEvaluator::Options::validate(const std::string& s) const
{
    if (!(time_tolerance > 0))
        core::throwConfigError(s, "time_tolerance", std::to_string(time_tolerance), "must be > 0");
    if (!(align_fit_distance >= 0))
        core::throwConfigError(s, "align_fit_distance", std::to_string(align_fit_distance),
                               "must be >= 0");
}

TrajectoryEvaluator::TrajectoryEvaluator(const Options& options) : options_(options)
{
    options_.validate();
}

TrajectoryEvaluator::Result TrajectoryEvaluator::evaluate(
    const std::vector<io::StampedPose2D>& estimate,
    const std::vector<io::StampedPose2D>& truth) const
{
    Result r;
    const auto pairs = associate(estimate, truth, options_);
    r.matched = pairs.size();
    r.unmatched = estimate.size() - pairs.size();

    if (options_.align)
    {
        std::vector<Eigen::Vector2d> src, dst;
        double travelled = 0;
        for (size_t i = 0; i < pairs.size(); ++i)
        {
            const auto& p = pairs[i];
            if (i > 0)
                travelled += std::hypot(p.truth.x - pairs[i - 1].truth.x,
                                        p.truth.y - pairs[i - 1].truth.y);
            if (options_.align_fit_distance > 0 && travelled > options_.align_fit_distance)
                break;
            src.emplace_back(p.est.x, p.est.y);
            dst.emplace_back(p.truth.x, p.truth.y);
        }
        if (const auto T = alignSE2(src, dst))
        {
            r.aligned = true;
            r.alignment = *T;
        }
    }

    double sum_sq = 0, sum = 0, sum_sq_phi = 0;
    for (const auto& p : pairs)
    {
        const Eigen::Vector2d e = r.alignment.apply({p.est.x, p.est.y});
        PoseError pe;
        pe.t = p.est.t;
        pe.dx = e.x() - p.truth.x;
        pe.dy = e.y() - p.truth.y;
        pe.dphi = wrapToPi(r.alignment.applyHeading(p.est.phi) - p.truth.phi);
        const double d = pe.position();
        sum_sq += d * d;
        sum += d;
        sum_sq_phi += pe.dphi * pe.dphi;
        r.position_max = std::max(r.position_max, d);
        r.heading_max = std::max(r.heading_max, std::abs(pe.dphi));
        r.errors.push_back(pe);
    }
    const double n = static_cast<double>(pairs.size());
    r.position_rmse = pairs.empty() ? kNaN : std::sqrt(sum_sq / n);
    r.position_mean = pairs.empty() ? kNaN : sum / n;
    r.heading_rmse = pairs.empty() ? kNaN : std::sqrt(sum_sq_phi / n);
    if (pairs.empty()) r.position_max = r.heading_max = kNaN;
    return r;
}

}  // namespace hymm::eval
