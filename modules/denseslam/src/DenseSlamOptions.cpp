// DenseSlam's options: [DenseSlam] keys (landmark_source, dense_layers, noise, ranges)
// and the sections of the dense part, and fromConfig.
#include "hymm/denseslam/DenseSlam.h"

#include <hymm/core/config_utils.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

namespace hymm::denseslam
{
namespace
{
constexpr double kDeg = M_PI / 180.0;

const std::pair<const char*, DenseSlam::LandmarkSource> kPointSources[] = {
    {"bearing_range", DenseSlam::LandmarkSource::BearingRange},
    {"laser_trees", DenseSlam::LandmarkSource::LaserTrees},
    {"both", DenseSlam::LandmarkSource::Both},
    {"laser_reflectors", DenseSlam::LandmarkSource::LaserReflectors},
    {"laser_reflectors_and_trees", DenseSlam::LandmarkSource::LaserReflectorsAndTrees}};

std::string sourceHelp()
{
    std::string h = "must be a comma-separated list of at most one of bearing_range, laser_trees, "
                    "both, laser_reflectors, laser_reflectors_and_trees and any of";
    for (const auto& k : landmarkSourceKinds()) h += " " + k.name;
    return h + " (each at most once)";
}

// landmark_source = point source and/or registered per-scan sources (DenseSlam.h).
void parseSources(const std::string& value, const std::string& section, DenseSlam::Options& o)
{
    std::string v;
    for (char c : value)
        if (c != ' ' && c != '\t') v += c;
    std::stringstream ss(v);
    std::string item;
    std::optional<DenseSlam::LandmarkSource> point;
    std::vector<std::string> scan;
    while (std::getline(ss, item, ','))
    {
        bool known = false;
        for (const auto& [name, src] : kPointSources)
            if (item == name && !point) point = src, known = true;
        if (!known && findLandmarkSourceKind(item) &&
            std::find(scan.begin(), scan.end(), item) == scan.end())
            scan.push_back(item), known = true;
        if (!known) core::throwConfigError(section, "landmark_source", value, sourceHelp());
    }
    if (!point && scan.empty()) core::throwConfigError(section, "landmark_source", value, sourceHelp());
    o.landmark_source = point.value_or(DenseSlam::LandmarkSource::None);
    o.scan_sources = std::move(scan);
}

std::string sourceName(const DenseSlam::Options& o)
{
    std::string out;
    for (const auto& [name, src] : kPointSources)
        if (src == o.landmark_source) out = name;
    for (const auto& s : o.scan_sources) out += (out.empty() ? "" : ",") + s;
    return out;
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
    parseSources(core::readString(cfg, s, "landmark_source", sourceName(*this)), s, *this);
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
    cfg.write(s, "landmark_source", sourceName(*this));
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
    return DenseSlam(o, e, t, r, d, &cfg);
}

}  // namespace hymm::denseslam
