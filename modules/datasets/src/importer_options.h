/**
 * @file importer_options.h
 * @brief Ini keys shared by the importers' Options (vehicle geometry, GPS filter).
 */
#pragma once

#include <hymm/core/UteVehicleModel.h>
#include <hymm/core/config_utils.h>

#include <string>
#include <vector>

#include "hymm/datasets/ground_truth.h"

namespace hymm::datasets::detail
{
inline const std::vector<std::string>& vehicleKeys()
{
    static const std::vector<std::string> k = {"L_m", "H_m", "a_m", "b_m"};
    return k;
}

inline void loadVehicle(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                        hymm::core::UteParams& p)
{
    p.L = hymm::core::readDoubleMin(cfg, section, "L_m", p.L, 0, true);
    p.H = hymm::core::readDouble(cfg, section, "H_m", p.H);
    p.a = hymm::core::readDouble(cfg, section, "a_m", p.a);
    p.b = hymm::core::readDouble(cfg, section, "b_m", p.b);
}

inline void saveVehicle(mrpt::config::CConfigFileBase& cfg, const std::string& section,
                        const hymm::core::UteParams& p)
{
    cfg.write(section, "L_m", p.L);
    cfg.write(section, "H_m", p.H);
    cfg.write(section, "a_m", p.a);
    cfg.write(section, "b_m", p.b);
}

inline const std::vector<std::string>& gpsKeys()
{
    static const std::vector<std::string> k = {"gps_max_speed_mps", "gps_reset_after"};
    return k;
}

inline void loadGps(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                    GpsFilterOptions& g)
{
    g.max_speed_mps =
        hymm::core::readDoubleMin(cfg, section, "gps_max_speed_mps", g.max_speed_mps, 0, true);
    const long n = hymm::core::readInt(cfg, section, "gps_reset_after",
                                       static_cast<long>(g.reset_after));
    if (n < 0)
        hymm::core::throwConfigError(section, "gps_reset_after", std::to_string(n),
                                     "must be >= 0");
    g.reset_after = static_cast<size_t>(n);
}

inline void saveGps(mrpt::config::CConfigFileBase& cfg, const std::string& section,
                    const GpsFilterOptions& g)
{
    cfg.write(section, "gps_max_speed_mps", g.max_speed_mps);
    cfg.write(section, "gps_reset_after", static_cast<int>(g.reset_after));
}

/** Concatenation of key lists, for checkKnownKeys. */
inline std::vector<std::string> joinKeys(std::initializer_list<std::vector<std::string>> lists)
{
    std::vector<std::string> out;
    for (const auto& l : lists) out.insert(out.end(), l.begin(), l.end());
    return out;
}

}  // namespace hymm::datasets::detail
