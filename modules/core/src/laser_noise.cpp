#include "hymm/core/laser_noise.h"

#include "hymm/core/config_utils.h"

#include <cmath>
#include <iostream>

namespace hymm::core
{
OptionTable LaserNoise::table()
{
    OptionTable t;
    t.real("std_range_m", std_range_m, "m", above(0, 10),
           "range noise of a laser return: delayed store covariances, particle and SOG sensor models, "
           "Scan-SLAM and HLL templates");
    t.real("std_bearing_deg", std_bearing_deg, "deg", openInterval(0, 60), "bearing noise of a laser return (same users)");
    return t;
}

void applyLaserNoise(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                     const std::string& range_key, const std::string& bearing_deg_key, double& range_m,
                     double& bearing_rad)
{
    LaserNoise laser;
    laser.table().load(cfg, "Laser");
    const std::pair<const std::string*, const char*> keys[] = {{&range_key, "std_range_m"},
                                                               {&bearing_deg_key, "std_bearing_deg"}};
    for (const auto& [key, laser_key] : keys)
    {
        if (!cfg.keyExists(section, *key)) continue;
        if (cfg.keyExists("Laser", laser_key))
            throwConfigError(section, *key, cfg.read_string(section, *key, "", false),
                             std::string("the laser noise is set in [Laser] ") + laser_key + "; remove this key");
        std::cerr << "warning: [" << section << "] " << *key << " is deprecated: set [Laser] " << laser_key
                  << " instead\n";
    }
    if (cfg.keyExists("Laser", "std_range_m")) range_m = laser.std_range_m;
    if (cfg.keyExists("Laser", "std_bearing_deg")) bearing_rad = M_PI / 180 * laser.std_bearing_deg;
}

}  // namespace hymm::core
