#include "hymm/datasets/VictoriaParkImporter.h"
#include <hymm/core/output_files.h>

#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <stdexcept>

#include "hymm/datasets/MatFile.h"
#include "hymm/datasets/RawlogWriter.h"
#include "hymm/datasets/import_dataset.h"
#include "hymm/datasets/text_table.h"
#include "importer_options.h"

namespace hymm::datasets
{
namespace
{
constexpr double kMsToS = 1e-3;
// Detections of one scan share the printed time stamp (ms resolution).
constexpr double kSameScanTolS = 1e-6;
// Bearings are printed with 5 decimals; allow their rounding at the 0 and pi ends.
constexpr double kBearingTolRad = 1e-4;

std::vector<double> column(const MatFile& f, const std::string& name)
{
    const Eigen::VectorXd v = f.readVector(name);
    return std::vector<double>(v.data(), v.data() + v.size());
}

void requireSameLength(const MatFile& f, size_t n, size_t m, const std::string& what)
{
    if (n != m)
        throw std::runtime_error("MAT file '" + f.path() + "': " + what + " have different lengths (" +
                                 std::to_string(n) + " vs " + std::to_string(m) + ")");
}

/** An empty observation of the tree detector at time t (the .mat time base). */
mrpt::obs::CObservationBearingRange::Ptr treeScan(const VictoriaParkImporter::Options& o, double t)
{
    auto scan = mrpt::obs::CObservationBearingRange::Create();
    scan->timestamp = mrpt::Clock::fromDouble(t + o.detections_time_offset_s);
    scan->sensorLabel = "TREES";
    scan->minSensorDistance = static_cast<float>(o.min_range_m);
    scan->maxSensorDistance = static_cast<float>(o.max_range_m);
    scan->fieldOfView_yaw = static_cast<float>(M_PI);
    scan->fieldOfView_pitch = 0;
    scan->sensor_std_range = static_cast<float>(o.std_range_m);
    scan->sensor_std_yaw = static_cast<float>(mrpt::DEG2RAD(o.std_bearing_deg));
    scan->sensor_std_pitch = 0;
    if (!o.track_laser)
        scan->sensorLocationOnRobot = mrpt::poses::CPose3D(o.vehicle.a, o.vehicle.b, 0, 0, 0, 0);
    return scan;
}

/** Why a detection is not used (the skip reason), nullptr when it is. */
const char* detectionProblem(const VictoriaParkImporter::Options& o, double range, double bearing)
{
    if (range < o.min_range_m || range > o.max_range_m) return "detection_out_of_range";
    if (bearing < -kBearingTolRad || bearing > M_PI + kBearingTolRad) return "detection_bad_bearing";
    return nullptr;
}

/** A detection: bearing from the laser's first beam (0..pi) to the vehicle's x axis. */
mrpt::obs::CObservationBearingRange::TMeasurement treeMeasurement(double range, double bearing)
{
    mrpt::obs::CObservationBearingRange::TMeasurement m;
    m.range = static_cast<float>(range);
    m.yaw = static_cast<float>(mrpt::math::wrapToPi(bearing - M_PI / 2));
    m.pitch = 0;
    m.landmarkID = -1;
    m.covariance.setZero();
    return m;
}

/** The side file of the trunk diameters, one line per detection of the rawlog. */
void writeDiameters(const std::string& path, const std::string& name,
                    const std::vector<mrpt::obs::CObservation::Ptr>& obs,
                    const std::vector<std::vector<double>>& diameters)
{
    hymm::core::AtomicTextFile f(path);
    f << "# trunk diameters of the detections in " << name
      << ".rawlog; t [s] rawlog time base\n# frame,t,index,range_m,yaw_rad,diameter_m\n"
      << std::setprecision(10);
    for (size_t k = 0; k < obs.size(); ++k)
    {
        const auto& o = dynamic_cast<const mrpt::obs::CObservationBearingRange&>(*obs[k]);
        for (size_t j = 0; j < o.sensedData.size(); ++j)
            f << k << ',' << mrpt::Clock::toDouble(o.timestamp) << ',' << j << ','
              << o.sensedData[j].range << ',' << o.sensedData[j].yaw << ','
              << diameters[k][j] << '\n';
    }
    f.commit();
}
}  // namespace

hymm::core::OptionTable VictoriaParkImporter::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.text("name", name, "prefix of the output files");
    t.include(detail::vehicleTable(vehicle));
    t.flag("track_laser", track_laser, "the robot frame is the laser (true) or the rear axle");
    t.real("detections_time_offset_s", detections_time_offset_s, "s", between(-1e6, 1e6),
           "added to every detection time");
    t.real("min_range_m", min_range_m, "m", atLeast(0, 10000), "nearer detections are skipped");
    t.real("max_range_m", max_range_m, "m", above(0, 10000),
           "farther detections are skipped (> min_range_m)");
    t.real("std_range_m", std_range_m, "m", above(0, 100), "range noise written to the rawlog");
    t.real("std_bearing_deg", std_bearing_deg, "deg", above(0, 180), "bearing noise written to the rawlog");
    t.include(detail::gpsTable(gps));
    t.include(odometry.table());
    return t;
}

void VictoriaParkImporter::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    table().load(cfg, section);
    if (!(max_range_m > min_range_m))
        hymm::core::throwConfigError(section, "max_range_m", std::to_string(max_range_m),
                                     "must be > min_range_m");
}

void VictoriaParkImporter::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    auto copy = *this;
    copy.table().save(cfg, section);
}

VictoriaParkImporter::Inputs VictoriaParkImporter::findInputs(
    const std::vector<std::string>& paths)
{
    Inputs in;
    in.dr_mat = findInputFile(paths, "aa3_dr.mat", true);
    in.detections = findInputFile(paths, "measurements.dat", true);
    in.gps_mat = findInputFile(paths, "aa3_gpsx.mat", false);
    return in;
}

std::vector<OdometryIntegrator::ControlSample> VictoriaParkImporter::readDeadReckoning(
    const std::string& path)
{
    const MatFile f(path);
    const auto t = column(f, "time"), v = column(f, "speed"), s = column(f, "steering");
    requireSameLength(f, t.size(), v.size(), "time and speed");
    requireSameLength(f, t.size(), s.size(), "time and steering");
    std::vector<OdometryIntegrator::ControlSample> out(t.size());
    for (size_t i = 0; i < t.size(); ++i) out[i] = {t[i] * kMsToS, v[i], s[i]};
    return out;
}

std::vector<hymm::io::StampedPose2D> VictoriaParkImporter::readGps(const std::string& path)
{
    const MatFile f(path);
    const auto t = column(f, "timeGps"), x = column(f, "Lo_m"), y = column(f, "La_m");
    requireSameLength(f, t.size(), x.size(), "timeGps and Lo_m");
    requireSameLength(f, t.size(), y.size(), "timeGps and La_m");
    std::vector<hymm::io::StampedPose2D> out(t.size());
    for (size_t i = 0; i < t.size(); ++i) out[i] = {t[i] * kMsToS, x[i], y[i], 0.0};
    return out;
}

std::vector<mrpt::obs::CObservation::Ptr> VictoriaParkImporter::readDetections(
    const std::string& path, ImportSummary& summary,
    std::vector<std::vector<double>>& diameters) const
{
    const auto table = readNumericTableLines(path, 4, &summary, "detection_malformed_line");
    checkTimeColumn(table, path, "detection");
    const auto& rows = table.rows;
    std::vector<mrpt::obs::CObservation::Ptr> out;
    diameters.clear();
    mrpt::obs::CObservationBearingRange::Ptr scan;
    double scan_t = -std::numeric_limits<double>::infinity();
    size_t dropped_scans = 0;
    const auto flush = [&]() {
        if (!scan) return;
        if (scan->sensedData.empty())
        {
            ++dropped_scans;
            diameters.pop_back();
        }
        else
            out.push_back(scan);
        scan.reset();
    };
    for (const auto& r : rows)
    {
        const double t = r[0], range = r[1], bearing = r[2], diameter = r[3];
        if (!std::isfinite(t) || !std::isfinite(range) || !std::isfinite(bearing))
        {
            summary.skip("detection_nan");
            continue;
        }
        if (t < scan_t - kSameScanTolS)
        {
            summary.skip("detection_non_monotonic");
            continue;
        }
        if (!scan || t > scan_t + kSameScanTolS)
        {  // a new scan starts
            flush();
            scan = treeScan(options_, t);
            diameters.emplace_back();
            scan_t = t;
        }
        if (const char* why = detectionProblem(options_, range, bearing))
        {
            summary.skip(why);
            continue;
        }
        scan->sensedData.push_back(treeMeasurement(range, bearing));
        diameters.back().push_back(diameter);
        ++summary.measurements;
    }
    flush();
    if (dropped_scans > 0) summary.skip("scan_without_valid_detections", dropped_scans);
    return out;
}

ImportSummary VictoriaParkImporter::run(const Inputs& in, const std::string& out_dir) const
{
    ImportSummary summary;
    summary.format = "victoria";
    ensureOutputDir(out_dir);
    const std::string base = out_dir + "/" + options_.name;

    // 1. Odometry: controls of the tracked point (laser or rear axle).
    hymm::core::UteParams model = options_.vehicle;
    if (!options_.track_laser) model.a = model.b = 0;
    const auto controls = OdometryIntegrator::sanitize(
        readDeadReckoning(in.dr_mat), OdometryIntegrator::Model::Ute, model, summary);
    summary.odometry_samples = controls.size();
    const OdometryIntegrator odo(OdometryIntegrator::Model::Ute, model, options_.odometry,
                                 controls);

    // 2. Detections, one observation per scan, on the .mat time base.
    std::vector<std::vector<double>> diameters;
    const auto obs = readDetections(in.detections, summary, diameters);
    if (obs.empty())
        throw std::runtime_error("no valid detection in '" + in.detections + "'");

    // 3. Rawlog and the diameters side file.
    writeOdometryRawlog(base + ".rawlog", odo, obs, summary);
    writeDiameters(base + "_tree_diameters.csv", options_.name, obs, diameters);
    summary.outputs.push_back(base + "_tree_diameters.csv");

    // 4. Ground truth: filtered GPS.
    if (!in.gps_mat.empty())
    {
        const auto gps = filterGpsFixes(readGps(in.gps_mat), options_.gps, summary);
        const std::string path = base + "_gps.tum";
        writeTumWithComment(
            path, gps,
            "Victoria Park GPS fixes (aa3_gpsx.mat), jumps filtered.\n"
            "t [s] = timeGps / 1000, the rawlog time base; x = Lo_m, y = La_m [local m].\n"
            "Heading unknown: the rotation (phi = 0) is a placeholder, not a heading.\n"
            "Position of the GPS antenna, not of the laser; the frame differs from the\n"
            "odometry frame by an unknown rigid transform.");
        summary.ground_truth_poses = gps.size();
        summary.outputs.push_back(path);
    }
    else
        summary.skip("gps_file_missing");
    return summary;
}

}  // namespace hymm::datasets
