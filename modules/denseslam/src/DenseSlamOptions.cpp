// DenseSlam's options: [DenseSlam] keys (landmark_source, dense_layers, noise, ranges)
// and the sections of the dense part, and fromConfig.
#include "hymm/denseslam/DenseSlam.h"

#include <hymm/core/OptionTable.h>
#include <hymm/dense/LayerRegistry.h>

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

std::string sourceNames()
{
    std::string h;
    for (const auto& k : pointSourceKinds()) h += (h.empty() ? "" : ", ") + k.name;
    for (const auto& [alias, names] : pointSourceAliases()) h += ", " + alias;
    for (const auto& k : landmarkSourceKinds()) h += ", " + k.name;
    return h;
}

std::string sourceHelp() { return "must be a comma-separated list of " + sourceNames() + " (each at most once)"; }

// landmark_source = registered point sources (or their aliases) and/or per-scan sources
// (LandmarkSources.h), each at most once.
void parseSources(const std::string& value, const std::string& section, DenseSlam::Options& o)
{
    std::string v;
    for (char c : value)
        if (c != ' ' && c != '\t') v += c;
    std::stringstream ss(v);
    std::string item;
    std::vector<std::string> point, scan;
    auto addOnce = [&](std::vector<std::string>& to, const std::string& name) {
        if (std::find(to.begin(), to.end(), name) != to.end())
            core::throwConfigError(section, "landmark_source", value, sourceHelp());
        to.push_back(name);
    };
    while (std::getline(ss, item, ','))
    {
        const auto alias = std::find_if(pointSourceAliases().begin(), pointSourceAliases().end(),
                                        [&](const auto& a) { return a.first == item; });
        if (alias != pointSourceAliases().end())
            for (const auto& name : alias->second) addOnce(point, name);
        else if (findPointSourceKind(item))
            addOnce(point, item);
        else if (findLandmarkSourceKind(item))
            addOnce(scan, item);
        else
            core::throwConfigError(section, "landmark_source", value, sourceHelp());
    }
    if (point.empty() && scan.empty()) core::throwConfigError(section, "landmark_source", value, sourceHelp());
    o.point_sources.clear();
    for (const auto& k : pointSourceKinds())
        if (std::find(point.begin(), point.end(), k.name) != point.end()) o.point_sources.push_back(k.name);
    o.scan_sources = std::move(scan);
}

// The list as written back: an alias where the point sources are exactly its sources.
std::string sourceName(const DenseSlam::Options& o)
{
    std::string out;
    for (const auto& [alias, names] : pointSourceAliases())
    {
        auto sorted = names;
        auto mine = o.point_sources;
        std::sort(sorted.begin(), sorted.end());
        std::sort(mine.begin(), mine.end());
        if (sorted == mine) out = alias;
    }
    if (out.empty())
        for (const auto& s : o.point_sources) out += (out.empty() ? "" : ",") + s;
    for (const auto& s : o.scan_sources) out += (out.empty() ? "" : ",") + s;
    return out;
}

std::string denseLayersHelp()
{
    return "must be none, or a comma-separated list of " + dense::layerKindNames() + " (each at most once)";
}

// dense_layers = none | comma-separated kinds of dense::layerKinds() (any order, each at
// most once, spaces allowed); kept in the table's order.
void parseDenseLayers(const std::string& value, const std::string& section, DenseSlam::Options& o)
{
    std::string v;
    for (char c : value)
        if (c != ' ' && c != '\t') v += c;
    o.dense_layers.clear();
    if (v == "none") return;
    std::stringstream ss(v);
    std::string item;
    std::vector<std::string> items;
    while (std::getline(ss, item, ','))
    {
        if (!dense::findLayerKind(item) || std::find(items.begin(), items.end(), item) != items.end())
            core::throwConfigError(section, "dense_layers", value, denseLayersHelp());
        items.push_back(item);
    }
    if (items.empty()) core::throwConfigError(section, "dense_layers", value, denseLayersHelp());
    for (const auto& kind : dense::layerKinds())
        if (std::find(items.begin(), items.end(), kind.name) != items.end()) o.dense_layers.emplace_back(kind.name);
}

std::string denseLayersName(const DenseSlam::Options& o)
{
    std::string out;
    for (const auto& name : o.dense_layers) out += (out.empty() ? "" : ",") + name;
    return out.empty() ? "none" : out;
}

std::string denseLayersRange()
{
    std::string out;
    for (const auto& kind : dense::layerKinds()) out += (out.empty() ? "`" : ", `") + std::string(kind.name) + "`";
    return "`none` or a list of " + out;
}
}  // namespace

core::OptionTable DenseSlam::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    OptionKey sources;
    sources.name = "landmark_source";
    sources.range = "a list of registered sources, each at most once: " + sourceNames();
    sources.doc = "where landmark observations come from (see Landmark sources)";
    sources.parse = [this](const std::string& s, const std::string& raw) { parseSources(raw, s, *this); };
    sources.format = [this]() { return sourceName(*this); };
    t.custom(std::move(sources));
    t.flag("use_landmark_ids", use_landmark_ids, "use the ids the rawlog carries; false: data association");
    t.real("odometry_cov_scale", odometry_cov_scale, "", above(0, 1e6), "multiplies the odometry covariance of the rawlog");
    t.real("odometry_std_xy", odometry_std_xy, "m", atLeast(0, 100), "added in quadrature to the odometry (per step)");
    t.real("odometry_std_phi_deg", odometry_std_phi, "deg", atLeast(0, 180),
           "added in quadrature to the odometry heading (per step)", kDeg);
    t.flag("turn_bias_state", turn_bias_state,
           "the wheels' unreported turn per metre as a filter state, learnt from the observations "
           "(and with [ScanOdometry] from its alignments); needs jacobians = current or first_estimates");
    t.real("turn_bias_prior_deg_per_m", turn_bias_prior, "deg/m", above(0, 180), "prior std of that turn", kDeg);
    t.real("turn_bias_walk_deg_per_m", turn_bias_walk, "deg/m/sqrt(m)", atLeast(0, 180),
           "its random walk per square root of a metre travelled", kDeg);
    t.choice("odometry_model", odometry_model,
             {{"thrun", OdometryModel::Thrun}, {"gaussian", OdometryModel::Gaussian}, {"none", OdometryModel::None}},
             "covariance of CObservationOdometry increments (observation-format rawlogs): MRPT's "
             "CActionRobotMovement2D Thrun model (its particles' covariance), MRPT's Gaussian model, or zero (OdometryModel.h)");
    t.real("odometry_thrun_alpha1_rot_rot", thrun.alpha1_rot_rot, "rad/rad", atLeast(0, 10),
           "thrun: rotation noise per rotation (MRPT alfa1_rot_rot)");
    t.real("odometry_thrun_alpha2_rot_trans_deg", thrun.alpha2_rot_trans, "deg/m", atLeast(0, 180),
           "thrun: rotation noise per metre (MRPT alfa2_rot_trans)", kDeg);
    t.real("odometry_thrun_alpha3_trans_trans", thrun.alpha3_trans_trans, "m/m", atLeast(0, 10),
           "thrun: translation noise per metre (MRPT alfa3_trans_trans)");
    t.real("odometry_thrun_alpha4_trans_rot", thrun.alpha4_trans_rot, "m/rad", atLeast(0, 10),
           "thrun: translation noise per radian turned (MRPT alfa4_trans_rot)");
    t.real("odometry_thrun_additional_std_xy", thrun.additional_std_xy, "m", atLeast(0, 10),
           "thrun: added to x and y (MRPT additional_std_XY)");
    t.real("odometry_thrun_additional_std_phi_deg", thrun.additional_std_phi, "deg", atLeast(0, 180),
           "thrun: added to the heading (MRPT additional_std_phi)", kDeg);
    t.real("sensor_std_range", sensor_std_range, "m", atLeast(0, 100),
           "> 0 overrides the range noise of every landmark observation");
    t.real("sensor_std_bearing_deg", sensor_std_bearing, "deg", atLeast(0, 90),
           "> 0 overrides the bearing noise of every landmark observation", kDeg);
    t.real("min_range", min_range, "m", atLeast(0, 1e5), "observations closer than this are skipped");
    t.real("max_range", max_range, "m", above(0, 1e9), "observations farther than this are skipped (> min_range)");
    t.flag("enable_profiler", enable_profiler, "CTimeLogger sections `denseslam.*`");
    OptionKey layers;
    layers.name = "dense_layers";
    layers.range = denseLayersRange();
    layers.doc = "layers of the HybridMetricMap; overrides `[HybridMetricMap] enable_*`";
    layers.parse = [this](const std::string& s, const std::string& raw) { parseDenseLayers(raw, s, *this); };
    layers.format = [this]() { return denseLayersName(*this); };
    t.custom(std::move(layers));
    t.flag("classic_grid", classic_grid, "also build the classic occupancy-grid baseline (`[ClassicOccupancyGrid]`)");
    t.real("laser_std_range", laser_std_range, "m", above(0, 10), "deprecated in hymm-slam: `[Laser] std_range_m`. Laser range noise (delayed store covariances)");
    t.real("laser_std_bearing_deg", laser_std_bearing, "deg", above(0, 60),
           "deprecated in hymm-slam: `[Laser] std_bearing_deg`. Laser bearing noise (delayed store covariances)", kDeg);
    t.real("max_local_std_m", max_local_std_m, "m", atLeast(0, 1000),
           "a scan is fused into a region only while its returns' error in the region's frame is at most this "
           "(Sec. 3.6, 3.7.3); 0 = always fuse");
    t.real("outside_cell_m", outside_cell_m, "m", above(0, 10),
           "returns in no region are tallied per cell of this size as they arrive (count and mean position) "
           "for the end-of-run diagnostic of why they fell outside: memory bounded by the area, not the run");
    t.flag("pose_landmark_vertices", pose_landmark_vertices,
           "regions also on the pose landmarks (scan landmarks, HLLs), a vertex at each one's frame origin "
           "(thesis 6.2, DenseSLAM on scan landmarks); false: on point landmarks only");
    t.real("same_object_distance_m", same_object_distance, "m", atLeast(0, 100),
           "laser_reflectors_and_trees: a tree this close to a reflector of the same scan is the same object; "
           "0 = beam overlap only");
    return t;
}

bool DenseSlam::Options::denseLayer(const std::string& kind) const
{
    return std::find(dense_layers.begin(), dense_layers.end(), kind) != dense_layers.end();
}

bool DenseSlam::Options::readsPoints(PointSourceInput input) const
{
    return std::any_of(point_sources.begin(), point_sources.end(), [&](const std::string& name) {
        const PointSourceKind* k = findPointSourceKind(name);
        return k && k->input == input;
    });
}

PointSourceSettings DenseSlam::Options::pointSettings() const
{
    PointSourceSettings s;
    s.min_range = min_range;
    s.max_range = max_range;
    s.sensor_std_range = sensor_std_range;
    s.sensor_std_bearing = sensor_std_bearing;
    s.use_landmark_ids = use_landmark_ids;
    return s;
}

void DenseSlam::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                            const std::string& s)
{
    table().load(cfg, s);
    if (!(max_range > min_range))
        core::throwConfigError(s, "max_range", core::formatReal(max_range), "must be > min_range");
}

void DenseSlam::Options::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                          const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void DenseSlam::DenseOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg)
{
    partition.loadFromConfigFile(cfg, "LtrPartition");
    virtual_landmarks.loadFromConfigFile(cfg, "VirtualLandmarks");
    delayed.loadFromConfigFile(cfg, "DelayedDenseStore");
    hybrid.loadAll(cfg);
    classic.loadFromConfigFile(cfg, "ClassicOccupancyGrid");
    dynamic.loadAll(cfg, "DynamicSlam");
    hll = hll::HighLevelLandmarks::loadOptions(&cfg);
    scan_odometry = scanslam::ScanOdometry::loadOptions(&cfg);
}

namespace
{
/** [Laser] owns the raw-return noise; the keys it replaces are deprecated (checked and
 *  applied per section by core::applyLaserNoise, as for the Scan-SLAM and HLL templates). */
void applyLaser(const mrpt::config::CConfigFileBase& cfg, DenseSlam::Options& o,
                dense::HybridMetricMap::Options& h)
{
    core::applyLaserNoise(cfg, "DenseSlam", "laser_std_range", "laser_std_bearing_deg", o.laser_std_range,
                          o.laser_std_bearing);
    // The layers keep their bearing noise in degrees: [Laser]'s value as written, not
    // the radians applyLaserNoise gives back.
    double bearing_rad = 0;
    core::applyLaserNoise(cfg, "ParticlesLayer", "range_std_m", "bearing_std_deg", h.particles.range_std_m,
                          bearing_rad);
    core::applyLaserNoise(cfg, "SogLayer", "range_std_m", "bearing_std_deg", h.sog.range_std_m, bearing_rad);
    if (cfg.keyExists("Laser", "std_bearing_deg"))
    {
        DenseSlam::LaserOptions laser;
        laser.table().load(cfg, "Laser");
        h.particles.bearing_std_deg = h.sog.bearing_std_deg = laser.std_bearing_deg;
    }
}
}  // namespace

DenseSlam DenseSlam::fromConfig(const mrpt::config::CConfigFileBase& cfg)
{
    Options o;
    o.loadFromConfigFile(cfg, "DenseSlam");
    ekf::EkfSlam::Options e;
    e.loadFromConfigFile(cfg, "EkfSlam");
    // Every point source reads (and checks) its sections, in use or not: a config may keep
    // the sections of a source it does not use.
    for (const auto& kind : pointSourceKinds()) kind.make(&cfg, o.pointSettings());
    DenseOptions d;
    d.loadFromConfigFile(cfg);
    applyLaser(cfg, o, d.hybrid);
    return DenseSlam(o, e, d, &cfg);
}

}  // namespace hymm::denseslam
