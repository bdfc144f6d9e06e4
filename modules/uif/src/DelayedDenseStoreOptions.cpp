/**
 * @file DelayedDenseStoreOptions.cpp
 * @brief [DelayedDenseStore] ini section (strict: unknown keys are errors).
 */
#include "hymm/uif/DelayedDenseStore.h"

#include <hymm/core/config_utils.h>

#include <sstream>

namespace hymm::uif
{
namespace
{
/** Ini integers are read and written as int: leave room for the ids taken above it. */
constexpr long kMaxFirstPassiveId = 2000000000;

std::string str(double v)
{
    std::ostringstream os;
    os << v;
    return os.str();
}
}  // namespace

hymm::core::OptionTable DelayedDenseStore::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.flag("enabled", enabled, "store returns in no region with their scan's pose as a passive state (Sec. 3.7)");
    t.flag("require_potential_region", require_potential_region,
           "store a return only inside a potential region (Sec. 3.7.3); false: every return in no region");
    t.integer("max_stored_points", max_stored_points, "returns", 1, 100000000, "returns kept at most");
    t.integer("max_stored_scans", max_stored_scans, "scans", 1, 100000, "passive EKF blocks at most");
    t.real("max_age_s", max_age_s, "s", atLeast(0, 1e7), "older scans are dropped; 0 = no limit");
    t.real("search_radius_m", search_radius_m, "m", above(0, 1e4), "potential-region vertices near the vehicle");
    t.integer("max_candidate_landmarks", max_candidate_landmarks, "", 3, 32,
              "nearest landmarks tried (k^3/6 triangles)");
    t.flag("fuse_free_space", fuse_free_space,
           "also fuse the free-space beam into a covering region created after the scan");
    t.integer("first_passive_id", first_passive_id, "", 0, kMaxFirstPassiveId,
              "passive ids are taken from here upwards");
    t.flag("enable_profiler", enable_profiler, "CTimeLogger sections `uif.*`");
    return t;
}

void DelayedDenseStore::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void DelayedDenseStore::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void DelayedDenseStore::Options::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    if (max_stored_points < 1) throwConfigError(s, "max_stored_points", "0", "must be >= 1");
    if (max_stored_scans < 1) throwConfigError(s, "max_stored_scans", "0", "must be >= 1");
    if (!(max_age_s >= 0.0)) throwConfigError(s, "max_age_s", str(max_age_s), "must be >= 0");
    if (!(search_radius_m > 0.0))
        throwConfigError(s, "search_radius_m", str(search_radius_m), "must be > 0");
    if (max_candidate_landmarks < 3 || max_candidate_landmarks > 32)
        throwConfigError(s, "max_candidate_landmarks", std::to_string(max_candidate_landmarks),
                         "must be in [3, 32] (the candidate search tries k^3/6 triangles)");
    if (first_passive_id < 0 || first_passive_id > kMaxFirstPassiveId)
        throwConfigError(s, "first_passive_id", std::to_string(first_passive_id),
                         "must be in [0, 2000000000]");
}

}  // namespace hymm::uif
