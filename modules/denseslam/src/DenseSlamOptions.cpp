// DenseSlam's options: [DenseSlam] keys (landmark_source, dense_layers, noise, ranges)
// and the sections of the dense part, and fromConfig.
#include "hymm/denseslam/DenseSlam.h"

#include <hymm/core/config_utils.h>

#include <cmath>
#include <sstream>
#include <string>

namespace hymm::denseslam
{
namespace
{
constexpr double kDeg = M_PI / 180.0;

DenseSlam::LandmarkSource parseSource(const std::string& s, const std::string& section)
{
    if (s == "bearing_range") return DenseSlam::LandmarkSource::BearingRange;
    if (s == "laser_trees") return DenseSlam::LandmarkSource::LaserTrees;
    if (s == "both") return DenseSlam::LandmarkSource::Both;
    if (s == "laser_reflectors") return DenseSlam::LandmarkSource::LaserReflectors;
    if (s == "laser_reflectors_and_trees")
        return DenseSlam::LandmarkSource::LaserReflectorsAndTrees;
    core::throwConfigError(section, "landmark_source", s,
                           "must be one of bearing_range, laser_trees, both, laser_reflectors, "
                           "laser_reflectors_and_trees");
}

const char* sourceName(DenseSlam::LandmarkSource s)
{
    switch (s)
    {
        case DenseSlam::LandmarkSource::BearingRange: return "bearing_range";
        case DenseSlam::LandmarkSource::LaserTrees: return "laser_trees";
        case DenseSlam::LandmarkSource::LaserReflectors: return "laser_reflectors";
        case DenseSlam::LandmarkSource::LaserReflectorsAndTrees:
            return "laser_reflectors_and_trees";
        default: return "both";
    }
}

const char* const kDenseLayersHelp =
    "must be none, or a comma-separated list of points, occupancy, particles, sog, property "
    "(each at most once)";

void parseDenseLayers(const std::string& value, const std::string& section,
                      DenseSlam::Options& o)
{
    bool* flags[] = {&o.dense_points, &o.dense_occupancy, &o.dense_particles, &o.dense_sog,
                     &o.dense_property};
    const char* names[] = {"points", "occupancy", "particles", "sog", "property"};
    for (bool* f : flags) *f = false;
    std::string v;
    for (char c : value)
        if (c != ' ' && c != '\t') v += c;
    if (v == "none") return;
    std::stringstream ss(v);
    std::string item;
    bool any = false;
    while (std::getline(ss, item, ','))
    {
        bool known = false;
        for (size_t k = 0; k < 5; ++k)
            if (item == names[k] && !*flags[k]) *flags[k] = known = true;
        if (!known) core::throwConfigError(section, "dense_layers", value, kDenseLayersHelp);
        any = true;
    }
    if (!any) core::throwConfigError(section, "dense_layers", value, kDenseLayersHelp);
}

std::string denseLayersName(const DenseSlam::Options& o)
{
    std::string out;
    const std::pair<bool, const char*> items[] = {{o.dense_points, "points"},
                                                  {o.dense_occupancy, "occupancy"},
                                                  {o.dense_particles, "particles"},
                                                  {o.dense_sog, "sog"},
                                                  {o.dense_property, "property"}};
    for (const auto& [on, name] : items)
        if (on) out += (out.empty() ? "" : ",") + std::string(name);
    return out.empty() ? "none" : out;
}
}  // namespace

void DenseSlam::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                            const std::string& s)
{
    core::checkKnownKeys(cfg, s,
                         {"landmark_source", "use_landmark_ids", "odometry_cov_scale",
                          "odometry_std_xy", "odometry_std_phi_deg", "sensor_std_range",
                          "sensor_std_bearing_deg", "min_range", "max_range", "enable_profiler",
                          "dense_layers", "classic_grid", "laser_std_range",
                          "laser_std_bearing_deg", "max_local_std_m", "same_object_distance_m"});
    landmark_source = parseSource(core::readString(cfg, s, "landmark_source", sourceName(landmark_source)), s);
    use_landmark_ids = core::readBool(cfg, s, "use_landmark_ids", use_landmark_ids);
    odometry_cov_scale = core::readDoubleMin(cfg, s, "odometry_cov_scale", odometry_cov_scale, 0.0, true);
    odometry_std_xy = core::readDoubleMin(cfg, s, "odometry_std_xy", odometry_std_xy, 0.0, false);
    odometry_std_phi =
        kDeg * core::readDoubleMin(cfg, s, "odometry_std_phi_deg", odometry_std_phi / kDeg, 0.0, false);
    sensor_std_range = core::readDoubleMin(cfg, s, "sensor_std_range", sensor_std_range, 0.0, false);
    sensor_std_bearing = kDeg * core::readDoubleMin(cfg, s, "sensor_std_bearing_deg",
                                                    sensor_std_bearing / kDeg, 0.0, false);
    min_range = core::readDoubleMin(cfg, s, "min_range", min_range, 0.0, false);
    max_range = core::readDoubleMin(cfg, s, "max_range", max_range, min_range, true);
    enable_profiler = core::readBool(cfg, s, "enable_profiler", enable_profiler);
    parseDenseLayers(core::readString(cfg, s, "dense_layers", denseLayersName(*this)), s, *this);
    classic_grid = core::readBool(cfg, s, "classic_grid", classic_grid);
    laser_std_range = core::readDoubleMin(cfg, s, "laser_std_range", laser_std_range, 0.0, true);
    laser_std_bearing = kDeg * core::readDoubleMin(cfg, s, "laser_std_bearing_deg",
                                                   laser_std_bearing / kDeg, 0.0, true);
    max_local_std_m = core::readDoubleMin(cfg, s, "max_local_std_m", max_local_std_m, 0.0, false);
    same_object_distance =
        core::readDoubleMin(cfg, s, "same_object_distance_m", same_object_distance, 0.0, false);
}

void DenseSlam::Options::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                          const std::string& s) const
{
    cfg.write(s, "landmark_source", sourceName(landmark_source));
    cfg.write(s, "use_landmark_ids", use_landmark_ids);
    cfg.write(s, "odometry_cov_scale", odometry_cov_scale);
    cfg.write(s, "odometry_std_xy", odometry_std_xy);
    cfg.write(s, "odometry_std_phi_deg", odometry_std_phi / kDeg);
    cfg.write(s, "sensor_std_range", sensor_std_range);
    cfg.write(s, "sensor_std_bearing_deg", sensor_std_bearing / kDeg);
    cfg.write(s, "min_range", min_range);
    cfg.write(s, "max_range", max_range);
    cfg.write(s, "enable_profiler", enable_profiler);
    cfg.write(s, "dense_layers", denseLayersName(*this));
    cfg.write(s, "classic_grid", classic_grid);
    cfg.write(s, "laser_std_range", laser_std_range);
    cfg.write(s, "laser_std_bearing_deg", laser_std_bearing / kDeg);
    cfg.write(s, "max_local_std_m", max_local_std_m);
    cfg.write(s, "same_object_distance_m", same_object_distance);
}

void DenseSlam::DenseOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg)
{
    partition.loadFromConfigFile(cfg, "LtrPartition");
    virtual_landmarks.loadFromConfigFile(cfg, "VirtualLandmarks");
    delayed.loadFromConfigFile(cfg, "DelayedDenseStore");
    hybrid.loadAll(cfg);
    classic.loadFromConfigFile(cfg, "ClassicOccupancyGrid");
    dynamic.loadAll(cfg, "DynamicSlam");
}

DenseSlam DenseSlam::fromConfig(const mrpt::config::CConfigFileBase& cfg)
{
    Options o;
    o.loadFromConfigFile(cfg, "DenseSlam");
    ekf::EkfSlam::Options e;
    e.loadFromConfigFile(cfg, "EkfSlam");
    extract::TreeExtractor::Options t;
    t.loadFromConfigFile(cfg, "TreeExtractor");
    extract::ReflectorExtractor::Options r;
    r.loadFromConfigFile(cfg, "ReflectorExtractor");
    DenseOptions d;
    d.loadFromConfigFile(cfg);
    return DenseSlam(o, e, t, r, d);
}

}  // namespace hymm::denseslam
