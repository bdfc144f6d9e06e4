#include "hymm/eval/LandmarkEvaluator.h"

#include <hymm/core/config_utils.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>

namespace hymm::eval
{
namespace
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Eigen::Vector2d truePosition(const io::LandmarkRecord& r) { return {r.x, r.y}; }

bool idsUsable(const std::vector<LandmarkEstimate>& est, const std::vector<io::LandmarkRecord>& truth)
{
    std::set<long> true_ids, seen;
    for (const auto& t : truth) true_ids.insert(t.id);
    for (const auto& e : est)
        if (!true_ids.count(e.id) || !seen.insert(e.id).second) return false;
    return !est.empty();
}

std::vector<std::pair<size_t, size_t>> associateById(
    const std::vector<LandmarkEstimate>& est, const std::vector<io::LandmarkRecord>& truth)
{
    std::map<long, size_t> by_id;
    for (size_t j = 0; j < truth.size(); ++j) by_id.emplace(truth[j].id, j);  // first wins
    std::vector<std::pair<size_t, size_t>> pairs;
    std::set<size_t> taken;
    for (size_t i = 0; i < est.size(); ++i)
    {
        const auto it = by_id.find(est[i].id);
        if (it != by_id.end() && taken.insert(it->second).second) pairs.emplace_back(i, it->second);
    }
    return pairs;
}

// Greedy global nearest neighbour: all candidate pairs within the gate, shortest first,
// each landmark used at most once.
std::vector<std::pair<size_t, size_t>> associateByDistance(
    const std::vector<Eigen::Vector2d>& est, const std::vector<io::LandmarkRecord>& truth,
    double gate)
{
    std::vector<std::tuple<double, size_t, size_t>> cand;
    for (size_t i = 0; i < est.size(); ++i)
        for (size_t j = 0; j < truth.size(); ++j)
        {
            const double d = (est[i] - truePosition(truth[j])).norm();
            if (d <= gate) cand.emplace_back(d, i, j);
        }
    std::sort(cand.begin(), cand.end());
    std::vector<bool> used_e(est.size(), false), used_t(truth.size(), false);
    std::vector<std::pair<size_t, size_t>> pairs;
    for (const auto& [d, i, j] : cand)
    {
        if (used_e[i] || used_t[j]) continue;
        used_e[i] = used_t[j] = true;
        pairs.emplace_back(i, j);
    }
    std::sort(pairs.begin(), pairs.end());
    return pairs;
}

/** The estimates in the ground-truth frame (unchanged without an alignment). */
std::vector<LandmarkEstimate> inTruthFrame(const std::vector<LandmarkEstimate>& estimates,
                                           const Se2Transform* alignment)
{
    std::vector<LandmarkEstimate> est = estimates;
    if (alignment)
    {
        const Eigen::Matrix2d R = alignment->rotation();
        for (auto& e : est)
        {
            e.position = alignment->apply(e.position);
            e.cov = R * e.cov * R.transpose();
        }
    }
    return est;
}

/** Nearest-neighbour pairs (estimate, truth) within `gate`. */
std::vector<std::pair<size_t, size_t>> associateByPosition(const std::vector<LandmarkEstimate>& est,
                                                           const std::vector<io::LandmarkRecord>& truth,
                                                           double gate)
{
    std::vector<Eigen::Vector2d> pos;
    for (const auto& e : est) pos.push_back(e.position);
    return associateByDistance(pos, truth, gate);
}
}  // namespace

std::vector<LandmarkEstimate> landmarkEstimatesFromRecords(
    const std::vector<io::LandmarkRecord>& records, int cov_column)
{
    std::vector<LandmarkEstimate> out;
    out.reserve(records.size());
    for (const auto& r : records)
    {
        LandmarkEstimate e;
        e.id = r.id;
        e.position = {r.x, r.y};
        if (cov_column >= 0)
        {
            const size_t c = static_cast<size_t>(cov_column);
            if (r.extra.size() < c + 3)
                throw std::invalid_argument(
                    "landmark " + std::to_string(r.id) + ": expected covariance (sxx, sxy, syy) in "
                    "extra columns " + std::to_string(c) + ".." + std::to_string(c + 2) + ", got " +
                    std::to_string(r.extra.size()) + " extra columns");
            e.has_cov = true;
            e.cov << r.extra[c], r.extra[c + 1], r.extra[c + 1], r.extra[c + 2];
        }
        out.push_back(e);
    }
    return out;
}

std::string LandmarkEvaluator::associationName(Association a)
{
    switch (a)
    {
        case Association::Auto: return "auto";
        case Association::Id: return "id";
        case Association::Nearest: return "nearest";
    }
    return "?";
}

LandmarkEvaluator::Association LandmarkEvaluator::parseAssociation(const std::string& name)
{
    if (name == "auto") return Association::Auto;
    if (name == "id") return Association::Id;
    if (name == "nearest") return Association::Nearest;
    throw std::invalid_argument("landmark association '" + name +
                                "' must be one of auto, id, nearest");
}

hymm::core::OptionTable LandmarkEvaluator::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.choice("association", association,
             {{"auto", Association::Auto}, {"id", Association::Id}, {"nearest", Association::Nearest}},
             "match estimated to true landmarks by ID, by nearest neighbour, or auto (ID when both carry them)");
    t.real("gate", gate, "m", above(0, 1e6), "largest distance of a nearest-neighbour match");
    return t;
}

void LandmarkEvaluator::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void LandmarkEvaluator::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void LandmarkEvaluator::Options::validate(const std::string& s) const
{
    if (!(gate > 0)) core::throwConfigError(s, "gate", std::to_string(gate), "must be > 0");
}

LandmarkEvaluator::LandmarkEvaluator(const Options& options) : options_(options)
{
    options_.validate();
}

LandmarkEvaluator::Result LandmarkEvaluator::evaluate(
    const std::vector<LandmarkEstimate>& estimates, const std::vector<io::LandmarkRecord>& truth,
    const Se2Transform* alignment) const
{
    const std::vector<LandmarkEstimate> est = inTruthFrame(estimates, alignment);

    Result r;
    r.used = options_.association;
    if (r.used == Association::Auto)
        r.used = idsUsable(est, truth) ? Association::Id : Association::Nearest;

    const std::vector<std::pair<size_t, size_t>> pairs =
        r.used == Association::Id ? associateById(est, truth) : associateByPosition(est, truth, options_.gate);

    double sum = 0, sum_sq = 0, sum_nees = 0;
    for (const auto& [i, j] : pairs)
    {
        Match m;
        m.estimate = i;
        m.truth = j;
        const Eigen::Vector2d err = est[i].position - truePosition(truth[j]);
        m.error = err.norm();
        sum += m.error;
        sum_sq += m.error * m.error;
        r.max_error = std::max(r.max_error, m.error);
        if (est[i].has_cov)
        {
            m.has_nees = true;
            m.nees = nees(err, est[i].cov);
            if (m.nees.ok())
            {
                ++r.nees_count;
                sum_nees += m.nees.value;
            }
            else
                ++r.nees_singular;
        }
        else
            m.nees = NeesValue{kNaN, NeesStatus::NotFinite};
        r.matches.push_back(m);
    }
    r.unmatched_estimates = est.size() - pairs.size();
    r.unmatched_truth = truth.size() - pairs.size();
    const double n = static_cast<double>(pairs.size());
    r.mean_error = pairs.empty() ? kNaN : sum / n;
    r.rmse = pairs.empty() ? kNaN : std::sqrt(sum_sq / n);
    if (pairs.empty()) r.max_error = kNaN;
    r.mean_nees = r.nees_count == 0 ? kNaN : sum_nees / static_cast<double>(r.nees_count);
    return r;
}

}  // namespace hymm::eval
