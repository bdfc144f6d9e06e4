#include <hymm/core/config_utils.h>
#include <hymm/ekf/EkfSlam.h>
#include <mrpt/core/bits_math.h>

#include <sstream>

namespace hymm::ekf
{
namespace
{
std::string str(double v)
{
    std::ostringstream os;
    os << v;
    return os.str();
}
}  // namespace

hymm::core::OptionTable EkfSlam::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.choice("association_method", association_method,
             {{"nn", AssociationMethod::NearestNeighbour}, {"jcbb", AssociationMethod::JCBB}},
             "association of observations without id: nearest neighbour (Eq. 2.60) or JCBB");
    t.real("association_gate_prob", association_gate_prob, "", openInterval(0, 1),
           "chi-square probability of the individual and joint association gates");
    t.real("creation_gate_prob", creation_gate_prob, "", openInterval(0, 1),
           "larger gate (> association_gate_prob): inside it for some landmark but unpaired = ambiguous");
    t.real("known_id_gate_prob", known_id_gate_prob, "", halfOpen(0, 1),
           "outlier gate for known-id observations: NIS above chi2inv(p, 2) rejected (`rejected_gate`); 0 = off");
    t.integer("jcbb_max_nodes", jcbb_max_nodes, "nodes", 0, 1000000000, "JCBB node budget per step (0: unlimited)");
    t.flag("prune_tentative", prune_tentative, "remove landmarks that are never confirmed");
    t.integer("confirm_min_observations", confirm_min_observations, "observations", 1, 1000,
              "a landmark is confirmed once used by this many observations (creation counts)");
    t.integer("confirm_window_steps", confirm_window_steps, "steps", 1, 100000,
              "unconfirmed landmarks older than this many update steps are removed");
    t.real("stabilising_std_xy", stabilising_std_xy, "m", atLeast(0, 100),
           "additive stabilising noise per prediction (Eq. 2.6's v), std dev");
    t.degrees("stabilising_std_phi_deg", stabilising_std_phi, atLeast(0, 180),
              "additive stabilising heading noise per prediction, std dev");
    t.flag("enable_profiler", enable_profiler, "CTimeLogger sections `ekf.*`");
    t.choice("jacobians", jacobians,
             {{"current", LinearisationPoint::Current},
              {"first_estimates", LinearisationPoint::FirstEstimates},
              {"invariant", LinearisationPoint::Invariant}},
             "linearisation points of the Jacobians (standard EKF, First-Estimates Jacobian EKF, or the "
             "right-invariant EKF: current Jacobians, updates applied on SE(2))");
    t.choice("pose_update_second_order", pose_update_second_order,
             {{"off", SecondOrderTerms::Off}, {"covariance", SecondOrderTerms::Covariance},
              {"full", SecondOrderTerms::Full}},
             "second-order terms of the pose-landmark update: none, S only, or S and the predicted observation");
    t.choice("iterated_covariance", iterated_covariance,
             {{"last_iterate", IteratedCovariance::LastIterate},
              {"first_estimates", IteratedCovariance::FirstEstimates}},
             "covariance of an iterated pose update: the last iterate's Jacobians, or the one-step update's "
             "(the FEJ-EKF's, or the invariant EKF's at the prior; needs jacobians = first_estimates or "
             "invariant; the mean stays the iterated one)");
    return t;
}

void EkfSlam::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void EkfSlam::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void EkfSlam::Options::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    if (!(association_gate_prob > 0.0 && association_gate_prob < 1.0))
        throwConfigError(s, "association_gate_prob", str(association_gate_prob), "must be in (0, 1)");
    if (!(creation_gate_prob > association_gate_prob && creation_gate_prob < 1.0))
        throwConfigError(s, "creation_gate_prob", str(creation_gate_prob),
                         "must be in (association_gate_prob, 1)");
    if (!(known_id_gate_prob >= 0.0 && known_id_gate_prob < 1.0))
        throwConfigError(s, "known_id_gate_prob", str(known_id_gate_prob),
                         "must be in [0, 1) (0: off)");
    if (confirm_min_observations < 1)
        throwConfigError(s, "confirm_min_observations", std::to_string(confirm_min_observations),
                         "must be >= 1");
    if (confirm_window_steps < 1)
        throwConfigError(s, "confirm_window_steps", std::to_string(confirm_window_steps),
                         "must be >= 1");
    if (!(stabilising_std_xy >= 0.0))
        throwConfigError(s, "stabilising_std_xy", str(stabilising_std_xy), "must be >= 0");
    if (!(stabilising_std_phi >= 0.0))
        throwConfigError(s, "stabilising_std_phi_deg", str(mrpt::RAD2DEG(stabilising_std_phi)),
                         "must be >= 0");
    if (iterated_covariance == IteratedCovariance::FirstEstimates && jacobians == LinearisationPoint::Current)
        throwConfigError(s, "iterated_covariance", "first_estimates", "needs jacobians = first_estimates or invariant");
}

}  // namespace hymm::ekf
