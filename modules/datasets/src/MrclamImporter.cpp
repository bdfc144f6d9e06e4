#include "hymm/datasets/MrclamImporter.h"

#include <hymm/core/config_utils.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "hymm/datasets/RawlogWriter.h"
#include "hymm/datasets/import_dataset.h"
#include "hymm/datasets/text_table.h"

namespace hymm::datasets
{
namespace
{
// Times are printed with 2-3 decimals (50 Hz); equal prints are one observation.
constexpr double kSameTimeTolS = 1e-6;

// An integer an int can hold (subject and barcode numbers are cast to int).
bool isInteger(double v)
{
    return std::isfinite(v) && v == std::floor(v) &&
           std::abs(v) <= static_cast<double>(std::numeric_limits<int>::max());
}

/** Largest rounding error of a time printed with 5 significant digits [s]. */
double printedTimeResolution(double t)
{
    constexpr int kSignificantDigits = 5;
    const double mag = std::floor(std::log10(std::max(std::abs(t), 1.0)));
    return 0.5 * std::pow(10.0, mag + 1 - kSignificantDigits) + 1e-9;
}

/**
 * Rebuilds the times of a fixed-rate table (column 0 of `rows`) as t0 + i * period
 * where they agree with the printed times within the printing resolution; counts the
 * rows whose time changed as repaired `what`_time_rounding.
 */
void restoreUniformTimes(std::vector<std::vector<double>>& rows, double period,
                         ImportSummary& summary, const std::string& what)
{
    if (period <= 0 || rows.empty() || !std::isfinite(rows[0][0])) return;
    const double t0 = rows[0][0];
    for (size_t i = 0; i < rows.size(); ++i)
    {
        const double t = t0 + static_cast<double>(i) * period;
        double& printed = rows[i][0];
        if (!std::isfinite(printed) || std::abs(printed - t) > printedTimeResolution(t))
            continue;  // not on the grid: keep the printed time
        if (std::abs(printed - t) > 1e-9) summary.repaired[what + "_time_rounding"]++;
        printed = t;
    }
}

/** An empty observation of the robot's camera (range and bearing to barcodes) at time t. */
mrpt::obs::CObservationBearingRange::Ptr landmarkObservation(const MrclamImporter::Options& o, double t)
{
    auto obs = mrpt::obs::CObservationBearingRange::Create();
    obs->timestamp = mrpt::Clock::fromDouble(t);
    obs->sensorLabel = "LANDMARKS";
    obs->minSensorDistance = 0;
    obs->maxSensorDistance = static_cast<float>(o.max_range_m);
    obs->fieldOfView_yaw = static_cast<float>(2 * M_PI);
    obs->fieldOfView_pitch = 0;
    obs->sensor_std_range = static_cast<float>(o.std_range_m);
    obs->sensor_std_yaw = static_cast<float>(mrpt::DEG2RAD(o.std_bearing_deg));
    obs->sensor_std_pitch = 0;
    return obs;
}

/** A measurement of the landmark `subject` (its id in the rawlog). */
mrpt::obs::CObservationBearingRange::TMeasurement landmarkMeasurement(double range, double bearing, int subject)
{
    mrpt::obs::CObservationBearingRange::TMeasurement m;
    m.range = static_cast<float>(range);
    m.yaw = static_cast<float>(mrpt::math::wrapToPi(bearing));
    m.pitch = 0;
    m.landmarkID = subject;
    m.covariance.setZero();
    return m;
}
}  // namespace

hymm::core::OptionTable MrclamImporter::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.text("name", name, "base name of the output files (empty: mrclam_robot<N>)");
    t.integer("robot", robot, "", 1, 1000, "robot converted (<= num_robots)");
    t.integer("num_robots", num_robots, "", 1, 1000, "robots in the dataset: their barcodes are not landmarks");
    t.real("max_range_m", max_range_m, "m", above(0, 10000), "farther measurements are skipped");
    t.real("std_range_m", std_range_m, "m", above(0, 100), "range noise written to the rawlog");
    t.real("std_bearing_deg", std_bearing_deg, "deg", above(0, 180), "bearing noise written to the rawlog");
    t.real("sample_period_s", sample_period_s, "s", atLeast(0, 3600),
           "odometry and ground-truth period, to rebuild times printed with 5 digits (0: keep them)");
    OptionKey fixes;
    fixes.name = "barcode_fixes";
    fixes.range = "list of `barcode:listed:actual`";
    fixes.doc = "subjects to correct in Barcodes.dat";
    fixes.parse = [this](const std::string& section, const std::string& raw) {
        barcode_fixes.clear();
        std::istringstream in(raw);
        for (std::string tok; in >> tok;)
        {
            BarcodeFix f;
            char c1 = 0, c2 = 0;
            std::istringstream ts(tok);
            if (!(ts >> f.barcode >> c1 >> f.listed >> c2 >> f.actual) || c1 != ':' || c2 != ':' ||
                ts.peek() != std::char_traits<char>::eof())
                throwConfigError(section, "barcode_fixes", raw,
                                 "'" + tok + "' is not barcode:listed_subject:actual_subject");
            barcode_fixes.push_back(f);
        }
    };
    fixes.format = [this]() {
        std::string out;
        for (const auto& f : barcode_fixes)
            out += (out.empty() ? "" : " ") + std::to_string(f.barcode) + ":" +
                   std::to_string(f.listed) + ":" + std::to_string(f.actual);
        return out;
    };
    t.custom(std::move(fixes));
    t.include(odometry.table());
    return t;
}

void MrclamImporter::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    table().load(cfg, section);
    if (robot > num_robots)
        hymm::core::throwConfigError(section, "robot", std::to_string(robot),
                                     "must be in 1.." + std::to_string(num_robots));
}

void MrclamImporter::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    auto copy = *this;
    copy.table().save(cfg, section);
}

MrclamImporter::MrclamImporter(const Options& options) : options_(options) {}

MrclamImporter::Inputs MrclamImporter::findInputs(const std::vector<std::string>& paths,
                                                  int robot)
{
    const std::string r = "Robot" + std::to_string(robot) + "_";
    Inputs in;
    in.odometry = findInputFile(paths, r + "Odometry.dat", true);
    in.measurements = findInputFile(paths, r + "Measurement.dat", true);
    in.barcodes = findInputFile(paths, "Barcodes.dat", true);
    in.landmarks = findInputFile(paths, "Landmark_Groundtruth.dat", false);
    in.groundtruth = findInputFile(paths, r + "Groundtruth.dat", false);
    return in;
}

std::map<int, int> MrclamImporter::readBarcodes(const std::string& path)
{
    std::map<int, int> out;
    for (const auto& row : readNumericTable(path, 2))
    {
        if (!isInteger(row[0]) || !isInteger(row[1]))
            throw std::runtime_error("'" + path + "': subject and barcode must be integers");
        const int subject = static_cast<int>(row[0]), barcode = static_cast<int>(row[1]);
        if (!out.emplace(barcode, subject).second)
            throw std::runtime_error("'" + path + "': barcode " + std::to_string(barcode) +
                                     " listed twice");
    }
    if (out.empty()) throw std::runtime_error("'" + path + "': no barcode found");
    return out;
}

std::map<int, int> MrclamImporter::barcodeMap(const std::string& path,
                                              ImportSummary& summary) const
{
    auto codes = readBarcodes(path);
    for (const auto& f : options_.barcode_fixes)
    {
        const auto it = codes.find(f.barcode);
        if (it == codes.end() || it->second != f.listed) continue;
        it->second = f.actual;
        summary.repaired["barcode_subject_fix"]++;
    }
    return codes;
}

std::vector<OdometryIntegrator::ControlSample> MrclamImporter::readOdometry(
    const std::string& path, ImportSummary& summary) const
{
    auto table = readNumericTableLines(path, 3, &summary, "odometry_malformed_line");
    if (table.rows.empty())
        throw std::runtime_error("'" + path + "' holds no odometry line (time v omega)");
    checkTimeColumn(table, path, "odometry");
    auto& rows = table.rows;
    restoreUniformTimes(rows, options_.sample_period_s, summary, "odometry");
    std::vector<OdometryIntegrator::ControlSample> raw;
    raw.reserve(rows.size());
    for (const auto& r : rows) raw.push_back({r[0], r[1], r[2]});
    auto out = OdometryIntegrator::sanitize(raw, OdometryIntegrator::Model::Unicycle,
                                            hymm::core::UteParams{}, summary);
    if (out.empty())
        throw std::runtime_error("'" + path + "': none of its " + std::to_string(rows.size()) +
                                 " odometry lines is usable (non-finite values)");
    return out;
}

std::vector<hymm::io::StampedPose2D> MrclamImporter::readGroundTruth(
    const std::string& path, ImportSummary& summary) const
{
    auto table = readNumericTableLines(path, 4, &summary, "groundtruth_malformed_line");
    checkTimeColumn(table, path, "ground-truth");
    auto& rows = table.rows;
    restoreUniformTimes(rows, options_.sample_period_s, summary, "groundtruth");
    std::vector<hymm::io::StampedPose2D> gt;
    gt.reserve(rows.size());
    for (const auto& r : rows)
    {
        if (!std::isfinite(r[0]) || !std::isfinite(r[1]) || !std::isfinite(r[2]) ||
            !std::isfinite(r[3]))
            summary.skip("groundtruth_nan");
        else if (!gt.empty() && !(r[0] > gt.back().t))
            summary.skip("groundtruth_non_monotonic");
        else
            gt.push_back({r[0], r[1], r[2], mrpt::math::wrapToPi(r[3])});
    }
    return gt;
}

std::vector<hymm::io::LandmarkRecord> MrclamImporter::readLandmarks(const std::string& path,
                                                                      ImportSummary& summary)
{
    // Surveyed positions are the ground truth every evaluation trusts: a value that is not
    // a finite number is an error, not a row to drop.
    std::vector<hymm::io::LandmarkRecord> lms;
    const auto table = readNumericTableLines(path, 5, &summary, "landmark_malformed_line");
    for (size_t i = 0; i < table.rows.size(); ++i)
    {
        const auto& r = table.rows[i];
        const std::string at = "'" + path + "' line " + std::to_string(table.lines[i]) + ": ";
        if (!isInteger(r[0]))
            throw std::runtime_error(at + "landmark subject number " + std::to_string(r[0]) +
                                     " is not an integer");
        for (size_t c = 1; c < 5; ++c)
            if (!std::isfinite(r[c]))
                throw std::runtime_error(at + "landmark " + std::to_string(static_cast<long>(r[0])) +
                                         " has a non-finite " +
                                         (c == 1 ? "x" : c == 2 ? "y" : "standard deviation"));
        lms.push_back({static_cast<long>(r[0]), r[1], r[2], {r[3], r[4]}});
    }
    return lms;
}

std::vector<mrpt::obs::CObservation::Ptr> MrclamImporter::readMeasurements(
    const std::string& path, const std::map<int, int>& barcode_to_subject,
    ImportSummary& summary) const
{
    std::vector<mrpt::obs::CObservation::Ptr> out;
    mrpt::obs::CObservationBearingRange::Ptr obs;
    double obs_t = -std::numeric_limits<double>::infinity();
    const auto flush = [&]() {
        if (obs && !obs->sensedData.empty()) out.push_back(obs);
        obs.reset();
    };
    const auto table = readNumericTableLines(path, 4, &summary, "measurement_malformed_line");
    checkTimeColumn(table, path, "measurement");
    for (const auto& r : table.rows)
    {
        const double t = r[0], range = r[2], bearing = r[3];
        if (!std::isfinite(t) || !isInteger(r[1]) || !std::isfinite(range) ||
            !std::isfinite(bearing))
        {
            summary.skip("measurement_nan");
            continue;
        }
        if (t < obs_t - kSameTimeTolS)
        {
            summary.skip("measurement_non_monotonic");
            continue;
        }
        const auto it = barcode_to_subject.find(static_cast<int>(r[1]));
        if (it == barcode_to_subject.end())
        {
            summary.skip("unknown_barcode");
            continue;
        }
        if (it->second >= 1 && it->second <= options_.num_robots)
        {
            summary.skip("robot_barcode");
            continue;
        }
        if (!(range > 0) || range > options_.max_range_m)
        {
            summary.skip("measurement_out_of_range");
            continue;
        }
        if (!obs || t > obs_t + kSameTimeTolS)
        {
            flush();
            obs = landmarkObservation(options_, t);
            obs_t = t;
        }
        obs->sensedData.push_back(landmarkMeasurement(range, bearing, it->second));
        ++summary.measurements;
    }
    flush();
    return out;
}

ImportSummary MrclamImporter::run(const Inputs& in, const std::string& out_dir) const
{
    ImportSummary summary;
    summary.format = "mrclam";
    ensureOutputDir(out_dir);
    const std::string name =
        options_.name.empty() ? "mrclam_robot" + std::to_string(options_.robot) : options_.name;
    const std::string base = out_dir + "/" + name;

    // 1. Odometry (unicycle: v, omega).
    const auto controls = readOdometry(in.odometry, summary);
    summary.odometry_samples = controls.size();
    const OdometryIntegrator odo(OdometryIntegrator::Model::Unicycle, hymm::core::UteParams{},
                                 options_.odometry, controls);

    // 2. Identified landmark measurements and rawlog.
    const auto obs = readMeasurements(in.measurements, barcodeMap(in.barcodes, summary), summary);
    if (obs.empty())
        throw std::runtime_error("no usable landmark measurement in '" + in.measurements + "'");
    writeOdometryRawlog(base + ".rawlog", odo, obs, summary);

    // 3. Ground truth: Vicon path and surveyed landmarks.
    if (!in.groundtruth.empty())
    {
        const auto gt = readGroundTruth(in.groundtruth, summary);
        hymm::io::writeTum(base + "_groundtruth.tum", gt);
        summary.ground_truth_poses = gt.size();
        summary.outputs.push_back(base + "_groundtruth.tum");
    }
    else
        summary.skip("groundtruth_file_missing");
    if (!in.landmarks.empty())
    {
        const auto lms = readLandmarks(in.landmarks, summary);
        hymm::io::writeLandmarksCsv(base + "_landmarks.csv", lms,
                                      "id,x,y,std_x,std_y (MRCLAM subject number; metres)");
        summary.landmarks = lms.size();
        summary.outputs.push_back(base + "_landmarks.csv");
    }
    else
        summary.skip("landmarks_file_missing");
    return summary;
}

}  // namespace hymm::datasets
