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

void DelayedDenseStore::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    using namespace hymm::core;
    checkKnownKeys(
        cfg, s,
        {"enabled", "require_potential_region", "max_stored_points", "max_stored_scans", "max_age_s",
         "search_radius_m", "max_candidate_landmarks", "fuse_free_space", "first_passive_id",
         "enable_profiler"});
    enabled = readBool(cfg, s, "enabled", enabled);
    require_potential_region = readBool(cfg, s, "require_potential_region", require_potential_region);
    const long pts = readInt(cfg, s, "max_stored_points", static_cast<long>(max_stored_points));
    if (pts < 1) throwConfigError(s, "max_stored_points", std::to_string(pts), "must be >= 1");
    max_stored_points = static_cast<size_t>(pts);
    const long scans = readInt(cfg, s, "max_stored_scans", static_cast<long>(max_stored_scans));
    if (scans < 1) throwConfigError(s, "max_stored_scans", std::to_string(scans), "must be >= 1");
    max_stored_scans = static_cast<size_t>(scans);
    max_age_s = readDoubleMin(cfg, s, "max_age_s", max_age_s, 0.0, false);
    search_radius_m = readDoubleMin(cfg, s, "search_radius_m", search_radius_m, 0.0, true);
    max_candidate_landmarks =
        static_cast<int>(readInt(cfg, s, "max_candidate_landmarks", max_candidate_landmarks));
    fuse_free_space = readBool(cfg, s, "fuse_free_space", fuse_free_space);
    first_passive_id = readInt(cfg, s, "first_passive_id", first_passive_id);
    enable_profiler = readBool(cfg, s, "enable_profiler", enable_profiler);
    validate(s);
}

void DelayedDenseStore::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    cfg.write(s, "enabled", enabled);
    cfg.write(s, "require_potential_region", require_potential_region);
    cfg.write(s, "max_stored_points", static_cast<int>(max_stored_points));
    cfg.write(s, "max_stored_scans", static_cast<int>(max_stored_scans));
    cfg.write(s, "max_age_s", max_age_s);
    cfg.write(s, "search_radius_m", search_radius_m);
    cfg.write(s, "max_candidate_landmarks", max_candidate_landmarks);
    cfg.write(s, "fuse_free_space", fuse_free_space);
    cfg.write(s, "first_passive_id", static_cast<int>(first_passive_id));
    cfg.write(s, "enable_profiler", enable_profiler);
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
