#include <hymm/core/config_utils.h>
#include <hymm/ekf/EkfSlam.h>
#include <mrpt/core/bits_math.h>

#include <sstream>

namespace hymm::ekf
{
namespace
{
std::string methodName(AssociationMethod m)
{
    return m == AssociationMethod::JCBB ? "jcbb" : "nn";
}
std::string jacobiansName(LinearisationPoint j)
{
    return j == LinearisationPoint::FirstEstimates ? "first_estimates" : "current";
}
std::string str(double v)
{
    std::ostringstream os;
    os << v;
    return os.str();
}
}  // namespace

void EkfSlam::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    using namespace hymm::core;
    checkKnownKeys(
        cfg, s,
        {"association_method", "association_gate_prob", "creation_gate_prob", "known_id_gate_prob",
         "jcbb_max_nodes",
         "prune_tentative", "confirm_min_observations", "confirm_window_steps",
         "stabilising_std_xy", "stabilising_std_phi_deg", "enable_profiler", "jacobians"});
    const std::string m = readString(cfg, s, "association_method", methodName(association_method));
    if (m == "nn")
        association_method = AssociationMethod::NearestNeighbour;
    else if (m == "jcbb")
        association_method = AssociationMethod::JCBB;
    else
        throwConfigError(s, "association_method", m, "must be nn or jcbb");
    association_gate_prob = readDouble(cfg, s, "association_gate_prob", association_gate_prob);
    creation_gate_prob = readDouble(cfg, s, "creation_gate_prob", creation_gate_prob);
    known_id_gate_prob = readDouble(cfg, s, "known_id_gate_prob", known_id_gate_prob);
    const long nodes = readInt(cfg, s, "jcbb_max_nodes", static_cast<long>(jcbb_max_nodes));
    if (nodes < 0) throwConfigError(s, "jcbb_max_nodes", std::to_string(nodes), "must be >= 0");
    jcbb_max_nodes = static_cast<size_t>(nodes);
    prune_tentative = readBool(cfg, s, "prune_tentative", prune_tentative);
    confirm_min_observations =
        static_cast<int>(readInt(cfg, s, "confirm_min_observations", confirm_min_observations));
    confirm_window_steps =
        static_cast<int>(readInt(cfg, s, "confirm_window_steps", confirm_window_steps));
    stabilising_std_xy = readDoubleMin(cfg, s, "stabilising_std_xy", stabilising_std_xy, 0.0, false);
    stabilising_std_phi = mrpt::DEG2RAD(readDoubleMin(
        cfg, s, "stabilising_std_phi_deg", mrpt::RAD2DEG(stabilising_std_phi), 0.0, false));
    enable_profiler = readBool(cfg, s, "enable_profiler", enable_profiler);
    const std::string j = readString(cfg, s, "jacobians", jacobiansName(jacobians));
    if (j == "current")
        jacobians = LinearisationPoint::Current;
    else if (j == "first_estimates")
        jacobians = LinearisationPoint::FirstEstimates;
    else
        throwConfigError(s, "jacobians", j, "must be current or first_estimates");
    validate(s);
}

void EkfSlam::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    cfg.write(s, "association_method", methodName(association_method));
    cfg.write(s, "association_gate_prob", association_gate_prob);
    cfg.write(s, "creation_gate_prob", creation_gate_prob);
    cfg.write(s, "known_id_gate_prob", known_id_gate_prob);
    cfg.write(s, "jcbb_max_nodes", static_cast<int>(jcbb_max_nodes));
    cfg.write(s, "prune_tentative", prune_tentative);
    cfg.write(s, "confirm_min_observations", confirm_min_observations);
    cfg.write(s, "confirm_window_steps", confirm_window_steps);
    cfg.write(s, "stabilising_std_xy", stabilising_std_xy);
    cfg.write(s, "stabilising_std_phi_deg", mrpt::RAD2DEG(stabilising_std_phi));
    cfg.write(s, "enable_profiler", enable_profiler);
    cfg.write(s, "jacobians", jacobiansName(jacobians));
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
}

}  // namespace hymm::ekf
