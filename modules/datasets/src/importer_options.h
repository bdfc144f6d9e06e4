/**
 * @file importer_options.h
 * @brief Ini keys shared by the importers' Options (vehicle geometry, GPS filter).
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <hymm/core/UteVehicleModel.h>
#include <hymm/core/config_utils.h>

#include <string>
#include <vector>

#include "hymm/datasets/ground_truth.h"

namespace hymm::datasets::detail
{
/** Vehicle geometry keys (UTE model, appendix A). */
inline hymm::core::OptionTable vehicleTable(hymm::core::UteParams& p)
{
    using namespace hymm::core;
    OptionTable t;
    t.real("L_m", p.L, "m", above(0, 100), "wheelbase");
    t.real("H_m", p.H, "m", between(-100, 100), "lateral offset of the encoder from the centre line");
    t.real("a_m", p.a, "m", between(-100, 100), "laser ahead of the rear axle");
    t.real("b_m", p.b, "m", between(-100, 100), "laser left of the centre line");
    return t;
}

/** GPS jump filter keys. */
inline hymm::core::OptionTable gpsTable(GpsFilterOptions& g)
{
    using namespace hymm::core;
    OptionTable t;
    t.real("gps_max_speed_mps", g.max_speed_mps, "m/s", above(0, 1000),
           "a fix implying a faster move from the last accepted one is a jump");
    t.integer("gps_reset_after", g.reset_after, "", 0, 1000000000,
              "consecutive rejected fixes after which the next is accepted anyway");
    return t;
}

/** Concatenation of key lists, for checkKnownKeys. */
inline std::vector<std::string> joinKeys(std::initializer_list<std::vector<std::string>> lists)
{
    std::vector<std::string> out;
    for (const auto& l : lists) out.insert(out.end(), l.begin(), l.end());
    return out;
}

}  // namespace hymm::datasets::detail
