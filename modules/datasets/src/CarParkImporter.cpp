#include "hymm/datasets/CarParkImporter.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "hymm/datasets/MatFile.h"
#include "hymm/datasets/RawlogWriter.h"
#include "hymm/datasets/import_dataset.h"
#include "importer_options.h"

namespace hymm::datasets
{
namespace
{
std::vector<double> column(const MatFile& f, const std::string& name)
{
    const Eigen::VectorXd v = f.readVector(name);
    return std::vector<double>(v.data(), v.data() + v.size());
}

void requireRows(const MatFile& f, const std::string& what, size_t n, size_t expected)
{
    if (n != expected)
        throw std::runtime_error("MAT file '" + f.path() + "': " + what + " has " +
                                 std::to_string(n) + " entries, expected " +
                                 std::to_string(expected));
}

/** An empty scan of n_beams beams of the car park's laser at time t. */
mrpt::obs::CObservation2DRangeScan::Ptr laserScan(const CarParkImporter::Options& o, double t, size_t n_beams,
                                                  bool has_intensity)
{
    auto scan = mrpt::obs::CObservation2DRangeScan::Create();
    scan->timestamp = mrpt::Clock::fromDouble(t);
    scan->sensorLabel = "LASER";
    scan->aperture = static_cast<float>(mrpt::DEG2RAD(o.aperture_deg));
    scan->rightToLeft = true;
    scan->maxRange = static_cast<float>(o.no_return_range_m);
    scan->stdError = static_cast<float>(o.range_std_m);
    if (!o.track_laser) scan->sensorPose = mrpt::poses::CPose3D(o.vehicle.a, o.vehicle.b, 0, 0, 0, 0);
    scan->resizeScan(n_beams);
    scan->setScanHasIntensity(has_intensity);
    return scan;
}

/** The surveyed beacons (estbeac, N x 2 or 2 x N), ids from 1; rows with a NaN skipped. */
std::vector<hymm::io::LandmarkRecord> readBeacons(const std::string& path, ImportSummary& summary)
{
    const MatFile bf(path);
    Eigen::MatrixXd b = bf.readMatrix("estbeac");
    if (b.cols() != 2 && b.rows() == 2) b.transposeInPlace();
    if (b.cols() != 2) throw std::runtime_error("MAT file '" + path + "': estbeac must be N x 2");
    std::vector<hymm::io::LandmarkRecord> lms;
    for (Eigen::Index i = 0; i < b.rows(); ++i)
    {
        if (!std::isfinite(b(i, 0)) || !std::isfinite(b(i, 1)))
        {
            summary.skip("beacon_nan");
            continue;
        }
        lms.push_back({static_cast<long>(i + 1), b(i, 0), b(i, 1), {}});
    }
    return lms;
}
}  // namespace

hymm::core::OptionTable CarParkImporter::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.text("name", name, "prefix of the output files");
    t.include(detail::vehicleTable(vehicle));
    t.flag("track_laser", track_laser, "the robot frame is the laser (true) or the rear axle");
    t.real("no_return_range_m", no_return_range_m, "m", above(0, 10000),
           "ranges at or beyond this are no-returns (> min_range_m)");
    t.real("min_range_m", min_range_m, "m", atLeast(0, 10000), "nearer returns are invalid");
    t.real("range_std_m", range_std_m, "m", above(0, 100), "range noise written to the rawlog");
    t.real("aperture_deg", aperture_deg, "deg", above(0, 360), "field of view of the scans");
    t.include(detail::gpsTable(gps));
    t.include(odometry.table());
    return t;
}

void CarParkImporter::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    table().load(cfg, section);
    if (!(no_return_range_m > min_range_m))
        hymm::core::throwConfigError(section, "no_return_range_m", std::to_string(no_return_range_m),
                                     "must be > min_range_m");
}

void CarParkImporter::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    auto copy = *this;
    copy.table().save(cfg, section);
}

CarParkImporter::Inputs CarParkImporter::findInputs(const std::vector<std::string>& paths)
{
    Inputs in;
    in.data_mat = findInputFile(paths, "data_set.mat", true);
    in.beacons_mat = findInputFile(paths, "beac_juan3.mat", false);
    return in;
}

std::vector<mrpt::obs::CObservation::Ptr> CarParkImporter::readScans(
    const MatFile& f, ImportSummary& summary) const
{
    const auto t = column(f, "TimeLaser");
    Eigen::MatrixXd ranges = f.readMatrix("Laser");
    Eigen::MatrixXd intensity = f.readMatrix("Intensity");
    // One scan per row; accept the transposed layout too.
    if (static_cast<size_t>(ranges.rows()) != t.size() &&
        static_cast<size_t>(ranges.cols()) == t.size())
        ranges.transposeInPlace();
    if (static_cast<size_t>(intensity.rows()) != t.size() &&
        static_cast<size_t>(intensity.cols()) == t.size())
        intensity.transposeInPlace();
    requireRows(f, "Laser", static_cast<size_t>(ranges.rows()), t.size());
    const bool has_intensity = intensity.size() > 0;
    if (has_intensity && (intensity.rows() != ranges.rows() || intensity.cols() != ranges.cols()))
        throw std::runtime_error("MAT file '" + f.path() +
                                 "': Intensity and Laser have different shapes");

    std::vector<mrpt::obs::CObservation::Ptr> out;
    double last_t = -std::numeric_limits<double>::infinity();
    const auto n_beams = static_cast<size_t>(ranges.cols());
    for (Eigen::Index i = 0; i < ranges.rows(); ++i)
    {
        if (!std::isfinite(t[i]))
        {
            summary.skip("scan_nan_time");
            continue;
        }
        if (!(t[i] > last_t))
        {
            summary.skip("scan_non_monotonic");
            continue;
        }
        last_t = t[i];
        auto scan = laserScan(options_, t[i], n_beams, has_intensity);
        size_t valid = 0;
        for (size_t j = 0; j < n_beams; ++j)
        {
            const double r = ranges(i, static_cast<Eigen::Index>(j));
            const bool ok =
                std::isfinite(r) && r >= options_.min_range_m && r < options_.no_return_range_m;
            scan->setScanRange(j, ok ? static_cast<float>(r) : 0.0f);
            scan->setScanRangeValidity(j, ok);
            if (has_intensity)
            {
                const double in = intensity(i, static_cast<Eigen::Index>(j));
                // Intensities are small non-negative integers in the file; anything an int
                // cannot hold is corrupt and stored as 0.
                const bool in_ok = std::isfinite(in) && std::abs(in) < 2.0e9;
                scan->setScanIntensity(j, in_ok ? static_cast<int>(in) : 0);
            }
            valid += ok ? 1 : 0;
        }
        summary.measurements += valid;
        summary.skip("beam_no_return_or_invalid", n_beams - valid);
        out.push_back(scan);
    }
    return out;
}

ImportSummary CarParkImporter::run(const Inputs& in, const std::string& out_dir) const
{
    ImportSummary summary;
    summary.format = "carpark";
    ensureOutputDir(out_dir);
    const std::string base = out_dir + "/" + options_.name;
    const MatFile data(in.data_mat);

    // 1. Odometry of the tracked point.
    hymm::core::UteParams model = options_.vehicle;
    if (!options_.track_laser) model.a = model.b = 0;
    const auto t = column(data, "Time_VS"), v = column(data, "Velocity"),
               s = column(data, "Steering");
    requireRows(data, "Velocity", v.size(), t.size());
    requireRows(data, "Steering", s.size(), t.size());
    std::vector<OdometryIntegrator::ControlSample> raw(t.size());
    for (size_t i = 0; i < t.size(); ++i) raw[i] = {t[i], v[i], s[i]};
    const auto controls =
        OdometryIntegrator::sanitize(raw, OdometryIntegrator::Model::Ute, model, summary);
    summary.odometry_samples = controls.size();
    const OdometryIntegrator odo(OdometryIntegrator::Model::Ute, model, options_.odometry,
                                 controls);

    // 2. Scans and rawlog.
    const auto scans = readScans(data, summary);
    if (scans.empty()) throw std::runtime_error("no valid laser scan in '" + in.data_mat + "'");
    writeOdometryRawlog(base + ".rawlog", odo, scans, summary);

    // 3. Ground truth: GPS and surveyed beacons.
    const auto tg = column(data, "TimeGPS"), gx = column(data, "GPSLon"),
               gy = column(data, "GPSLat");
    requireRows(data, "GPSLon", gx.size(), tg.size());
    requireRows(data, "GPSLat", gy.size(), tg.size());
    std::vector<hymm::io::StampedPose2D> gps_raw(tg.size());
    for (size_t i = 0; i < tg.size(); ++i) gps_raw[i] = {tg[i], gx[i], gy[i], 0.0};
    const auto gps = filterGpsFixes(gps_raw, options_.gps, summary);
    writeTumWithComment(base + "_gps.tum", gps,
                        "ACFR car park GPS fixes (data_set.mat), jumps filtered.\n"
                        "t [s] = TimeGPS, the rawlog time base; x = GPSLon, y = GPSLat [local m].\n"
                        "Heading unknown: the rotation (phi = 0) is a placeholder, not a heading.\n"
                        "Same frame as the beacons file; differs from the odometry frame by an\n"
                        "unknown rigid transform.");
    summary.ground_truth_poses = gps.size();
    summary.outputs.push_back(base + "_gps.tum");

    if (!in.beacons_mat.empty())
    {
        const auto lms = readBeacons(in.beacons_mat, summary);
        hymm::io::writeLandmarksCsv(
            base + "_beacons.csv", lms,
            "id,x,y (beacons surveyed with kinematic GPS, beac_juan3.mat estbeac; GPS frame)");
        summary.landmarks = lms.size();
        summary.outputs.push_back(base + "_beacons.csv");
    }
    else
        summary.skip("beacons_file_missing");
    return summary;
}

}  // namespace hymm::datasets
