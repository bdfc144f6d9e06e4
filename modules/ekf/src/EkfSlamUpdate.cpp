// EkfSlam: one observation step (validation, association, fusion, augmentation, pruning).
#include <hymm/core/RangeBearingModel.h>
#include <hymm/core/TimeLogger.h>
#include <hymm/ekf/EkfSlam.h>
#include <mrpt/math/distributions.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "batch_products.h"

namespace hymm::ekf
{
namespace
{
bool isValid(const RangeBearingObs& o)
{
    if (!o.z.allFinite() || !o.R.allFinite() || o.z[0] < 0.0) return false;
    if (std::abs(o.R(0, 1) - o.R(1, 0)) > 1e-12 * (1.0 + o.R.cwiseAbs().maxCoeff())) return false;
    Eigen::LLT<Eigen::Matrix2d> llt(o.R);
    return llt.info() == Eigen::Success;
}
}  // namespace

UpdateReport EkfSlam::updateRangeBearing(
    const std::vector<RangeBearingObs>& obs, const mrpt::poses::CPose3D& sensorPoseOnVehicle)
{
    core::TimedSection tle_all(profiler_, "ekf.update_step");
    const Eigen::Vector3d sensor(
        sensorPoseOnVehicle.x(), sensorPoseOnVehicle.y(), sensorPoseOnVehicle.yaw());
    if (!sensor.allFinite())
        throw std::invalid_argument("EkfSlam::updateRangeBearing: non-finite sensor pose on the vehicle");
    UpdateReport report;
    report.assigned_ids.assign(obs.size(), -1);

    // 1. Invalid observations are skipped and counted, so one bad detection cannot abort a run.
    std::vector<bool> valid(obs.size());
    for (size_t i = 0; i < obs.size(); ++i)
    {
        valid[i] = isValid(obs[i]);
        if (!valid[i]) ++report.rejected_invalid;
    }

    // 2. Data association: known ids, then NN or JCBB for the rest.
    std::vector<Pairing> pairs;
    std::vector<NewLandmark> created;
    {
        core::TimedSection tle(profiler_, "ekf.2_associate");
        associateBatch(obs, valid, sensor, pairs, created, report);
    }

    // 3. One batched update with every associated observation.
    if (!pairs.empty())
    {
        core::TimedSection tle(profiler_, "ekf.3_update");
        if (fuse(pairs, obs, report.rejection_reason))
        {
            report.associated += pairs.size();
            for (const auto& pr : pairs)
            {
                report.assigned_ids[pr.obs] = pr.id;
                ++layout_.get(pr.id).times_seen;
            }
        }
        else
            report.rejected_numeric += pairs.size();
    }

    // 4. New landmarks at the updated vehicle pose (Eq. 2.53), all in one augmentation.
    if (!created.empty())
    {
        core::TimedSection tle(profiler_, "ekf.4_augment");
        addNewLandmarks(created, obs, sensor, report);
    }

    // 5. End of step: confirm or prune tentative landmarks.
    {
        core::TimedSection tle(profiler_, "ekf.5_prune");
        report.pruned = pruneTentative();
    }
    ++step_;
    return report;
}

void EkfSlam::associateBatch(
    const std::vector<RangeBearingObs>& obs, const std::vector<bool>& valid,
    const Eigen::Vector3d& sensor, std::vector<Pairing>& pairs, std::vector<NewLandmark>& created,
    UpdateReport& report) const
{
    // Known associations first; an unknown known-id starts a landmark with that id.
    std::vector<bool> taken(layout_.numLandmarks(), false);  // by block position
    const std::vector<size_t> unknown = associateKnownIds(obs, valid, sensor, pairs, created, taken, report);
    if (unknown.empty()) return;

    // Individual gate against every free point landmark with its marginal S (O(n) small
    // blocks); landmarks inside some observation's creation gate become the candidates.
    const double creation_gate = mrpt::math::chi2inv(options_.creation_gate_prob, 2);
    const std::vector<Pairing> cand = gateCandidates(obs, unknown, taken, sensor);

    AssociationProblem prob;
    for (size_t i : unknown)
    {
        prob.z.push_back(obs[i].z);
        prob.R.push_back(obs[i].R);
    }
    const auto kc = static_cast<Eigen::Index>(cand.size());
    for (const auto& pr : cand) prob.h.push_back(pr.h);
    // Joint C = H P H^T over the candidates, from gathered P H^T columns (O(n k + k^2)).
    prob.C = detail::projectPHt(detail::gatherPHt(activeP(), cand), cand);
    prob.C = (0.5 * (prob.C + prob.C.transpose())).eval();

    const AssociationResult res = associate(
        prob, options_.association_method, options_.association_gate_prob, options_.jcbb_max_nodes);
    report.jcbb_nodes = res.jcbb_nodes;

    // Unpaired observations: inside the association gate of a landmark -> rejected by the
    // joint/conflict test; inside only the creation gate -> ambiguous; else a new landmark.
    const double assoc_gate = mrpt::math::chi2inv(options_.association_gate_prob, 2);
    for (size_t u = 0; u < unknown.size(); ++u)
    {
        const size_t i = unknown[u];
        const int j = res.assignment[u];
        if (j >= 0)
        {
            Pairing pr = cand[static_cast<size_t>(j)];
            pr.obs = i;
            pairs.push_back(pr);
            continue;
        }
        const double dmin = kc > 0 ? res.d2.row(static_cast<Eigen::Index>(u)).minCoeff()
                                   : std::numeric_limits<double>::infinity();
        if (dmin < assoc_gate)
            ++report.rejected_gate;
        else if (dmin < creation_gate)
            ++report.ambiguous;
        else
            created.push_back({i, -1});
    }
}

std::vector<size_t> EkfSlam::associateKnownIds(
    const std::vector<RangeBearingObs>& obs, const std::vector<bool>& valid,
    const Eigen::Vector3d& sensor, std::vector<Pairing>& pairs, std::vector<NewLandmark>& created,
    std::vector<bool>& taken, UpdateReport& report) const
{
    std::vector<size_t> unknown;
    std::vector<long> claimed_new;
    const double known_gate = options_.known_id_gate_prob > 0.0
                                  ? mrpt::math::chi2inv(options_.known_id_gate_prob, 2)
                                  : 0.0;
    for (size_t i = 0; i < obs.size(); ++i)
    {
        if (!valid[i]) continue;
        const long id = obs[i].id;
        if (id < 0)
        {
            unknown.push_back(i);
            continue;
        }
        if (!layout_.has(id))
        {
            bool dup = false;
            for (long c : claimed_new) dup = dup || c == id;
            if (dup)
                ++report.rejected_gate;  // two detections with the same new id in one batch
            else
            {
                created.push_back({i, id});
                claimed_new.push_back(id);
            }
            continue;
        }
        const LandmarkBlock& b = layout_.get(id);
        if (b.dim != 2)
        {
            ++report.rejected_gate;
            continue;
        }
        Pairing pr = makePairing(i, b, sensor);
        if (known_gate > 0.0)
        {
            // Individual NIS with the marginal S of this landmark (Eq. 2.58).
            const auto o = static_cast<Eigen::Index>(b.offset);
            const Eigen::Matrix2d cross = pr.Hv * activeP().block<3, 2>(0, o) * pr.Hl.transpose();
            const Eigen::Matrix2d S = pr.Hv * activeP().topLeftCorner<3, 3>() * pr.Hv.transpose() +
                                      cross + cross.transpose() +
                                      pr.Hl * activeP().block<2, 2>(o, o) * pr.Hl.transpose() + obs[i].R;
            const Eigen::Vector2d nu = rangeBearingInnovation(obs[i].z, pr.h);
            if (!(nu.dot(S.ldlt().solve(nu)) < known_gate))
            {
                ++report.rejected_gate;
                continue;
            }
        }
        pairs.push_back(pr);
        for (size_t k = 0; k < layout_.blocks().size(); ++k)
            if (layout_.blocks()[k].id == id) taken[k] = true;
    }
    return unknown;
}

std::vector<EkfSlam::Pairing> EkfSlam::gateCandidates(
    const std::vector<RangeBearingObs>& obs, const std::vector<size_t>& unknown,
    const std::vector<bool>& taken, const Eigen::Vector3d& sensor) const
{
    const double creation_gate = mrpt::math::chi2inv(options_.creation_gate_prob, 2);
    std::vector<Pairing> cand;
    const Eigen::Matrix3d Pvv = activeP().topLeftCorner<3, 3>();
    for (size_t k = 0; k < layout_.blocks().size(); ++k)
    {
        const LandmarkBlock& b = layout_.blocks()[k];
        if (b.dim != 2 || taken[k]) continue;
        const auto o = static_cast<Eigen::Index>(b.offset);
        Pairing pr = makePairing(0, b, sensor);
        const Eigen::Matrix2d Pvl_term = pr.Hv * activeP().block<3, 2>(0, o) * pr.Hl.transpose();
        const Eigen::Matrix2d S0 = pr.Hv * Pvv * pr.Hv.transpose() + Pvl_term +
                                   Pvl_term.transpose() +
                                   pr.Hl * activeP().block<2, 2>(o, o) * pr.Hl.transpose();
        bool near = false;
        for (size_t i : unknown)
        {
            const Eigen::Matrix2d S = S0 + obs[i].R;
            const Eigen::Vector2d nu = rangeBearingInnovation(obs[i].z, pr.h);
            const double d2 = nu.dot(S.ldlt().solve(nu));
            if (d2 < creation_gate) near = true;
        }
        if (near) cand.push_back(pr);
    }
    return cand;
}

void EkfSlam::addNewLandmarks(const std::vector<NewLandmark>& created,
                              const std::vector<RangeBearingObs>& obs, const Eigen::Vector3d& sensor,
                              UpdateReport& report)
{
    const auto k = static_cast<Eigen::Index>(created.size());
    Eigen::MatrixXd G(2 * k, 3), noise = Eigen::MatrixXd::Zero(2 * k, 2 * k);
    std::vector<std::pair<long, Eigen::VectorXd>> blocks;
    long next_id = layout_.nextFreeId();
    for (const auto& c : created)  // known ids must not be reused by fresh ones
        if (c.id >= next_id) next_id = c.id + 1;
    for (Eigen::Index a = 0; a < k; ++a)
    {
        const NewLandmark& c = created[static_cast<size_t>(a)];
        hymm::core::Mat23 Gv;
        hymm::core::Mat2 Gz;
        const Eigen::Vector2d lm =
            hymm::core::inverseRangeBearing(x_.head<3>(), sensor, obs[c.obs].z, &Gv, &Gz);
        G.middleRows<2>(2 * a) = Gv;
        noise.block<2, 2>(2 * a, 2 * a) = Gz * obs[c.obs].R * Gz.transpose();
        const long id = c.id >= 0 ? c.id : next_id++;
        blocks.emplace_back(id, lm);
        report.assigned_ids[c.obs] = id;
    }
    augment(blocks, G, noise, false);
    report.created += created.size();
}

size_t EkfSlam::pruneTentative()
{
    std::vector<long> doomed;
    for (auto& b : layout_.blocks())
    {
        if (b.confirmed) continue;
        if (b.times_seen >= options_.confirm_min_observations)
            b.confirmed = true;
        else if (options_.prune_tentative && step_ - b.created_step >= options_.confirm_window_steps)
            doomed.push_back(b.id);
    }
    for (long id : doomed) removeLandmark(id);
    return doomed.size();
}

}  // namespace hymm::ekf
