/**
 * @file RegionPartitionOptions.cpp
 * @brief [LtrPartition]: the partition's keys, declared once (loader, saver, README
 *        table), and their checks.
 */
#include "hymm/ltr/RegionPartition.h"

#include <hymm/core/config_utils.h>

#include <string>

namespace hymm::ltr
{
hymm::core::OptionTable RegionPartition::Options::table()
{
    using namespace hymm::core;
    OptionTable t = conditions.table();
    t.real("search_radius_m", search_radius_m, "m", above(0, 1e4), "candidate vertices lie this close to the vehicle");
    t.real("grid_cell_size_m", grid_cell_size_m, "m", above(0, 1e4), "cell of the point-lookup grid");
    t.integer("max_new_regions_per_update", max_new_regions_per_update, "", 0, 100000,
              "bound on the regions created per update");
    t.integer("max_seed_landmarks", max_seed_landmarks, "", 3, 1000,
              "nearest eligible landmarks tried when seeding");
    t.flag("local_refresh", local_refresh,
           "grow around the vehicle only (updateNear); far regions refreshed after a large correction");
    t.real("full_refresh_correction_m", full_refresh_correction_m, "m", atLeast(0, 1e4),
           "with local_refresh: a larger vehicle correction refreshes every region");
    return t;
}

void RegionPartition::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void RegionPartition::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void RegionPartition::Options::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    conditions.validate(s);
    if (!(search_radius_m > 0))
        throwConfigError(s, "search_radius_m", std::to_string(search_radius_m), "must be > 0");
    if (!(grid_cell_size_m > 0))
        throwConfigError(s, "grid_cell_size_m", std::to_string(grid_cell_size_m), "must be > 0");
    if (max_new_regions_per_update < 0)
        throwConfigError(
            s, "max_new_regions_per_update", std::to_string(max_new_regions_per_update),
            "must be >= 0");
    if (max_seed_landmarks < 3)
        throwConfigError(
            s, "max_seed_landmarks", std::to_string(max_seed_landmarks), "must be >= 3");
    if (!(full_refresh_correction_m >= 0))
        throwConfigError(
            s, "full_refresh_correction_m", std::to_string(full_refresh_correction_m),
            "must be >= 0");
}

}  // namespace hymm::ltr
