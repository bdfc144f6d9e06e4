/**
 * @file NoiseCalibration.cpp
 * @brief Robust range/bearing residual statistics against a ground-truth track, the
 *        options, and the calibration of an MRCLAM robot (odometry part:
 *        NoiseCalibrationOdometry.cpp).
 */
#include "hymm/datasets/NoiseCalibration.h"

#include <hymm/core/config_utils.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "hymm/datasets/MrclamImporter.h"
#include "hymm/datasets/import_dataset.h"
#include "noise_calibration_track.h"

namespace hymm::datasets
{
namespace
{
using detail::madStd;
using detail::median;
using detail::Track;
using hymm::io::StampedPose2D;

ResidualStats robustStats(const std::vector<double>& e, double threshold)
{
    ResidualStats s;
    s.used = e.size();
    s.median = median(e);
    s.mad_std = madStd(e, s.median);
    double sum = 0, sum2 = 0;
    size_t n = 0;
    for (double x : e)
    {
        if (std::abs(x - s.median) > threshold * s.mad_std)
        {
            ++s.outliers;
            continue;
        }
        sum += x, sum2 += x * x, ++n;
    }
    if (n > 0)
    {
        s.inlier_mean = sum / static_cast<double>(n);
        s.inlier_std =
            std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - s.inlier_mean * s.inlier_mean));
    }
    s.model_std = std::hypot(s.median, s.mad_std);
    std::vector<double> sorted = e;
    std::sort(sorted.begin(), sorted.end());
    const auto q = [&sorted](double p) {
        return sorted[static_cast<size_t>(std::floor(p * static_cast<double>(sorted.size() - 1)))];
    };
    s.p01 = q(0.01), s.p99 = q(0.99);
    return s;
}

/** Residuals of the measurements of surveyed landmarks inside the ground truth. */
struct Residuals
{
    std::vector<double> er, eb, range;  // range [m] and bearing [deg] residuals, measured range
    std::vector<long> ids;              // landmark label
    std::vector<StampedPose2D> poses;   // interpolated truth pose
};

Residuals residualsOf(const std::vector<LandmarkMeasurement>& measurements, const Track& track,
                      const std::map<long, Eigen::Vector2d>& lm, std::map<std::string, size_t>& skipped)
{
    Residuals res;
    for (const auto& m : measurements)
    {
        const auto it = lm.find(m.id);
        if (it == lm.end())
        {
            skipped["measurement_unknown_landmark"]++;
            continue;
        }
        StampedPose2D p;
        std::string why;
        if (!track.interpolate(m.t, p, why))
        {
            skipped[why]++;
            continue;
        }
        const Eigen::Vector2d d = it->second - Eigen::Vector2d(p.x, p.y);
        res.er.push_back(m.range - d.norm());
        res.eb.push_back(mrpt::RAD2DEG(mrpt::math::wrapToPi(m.bearing - (std::atan2(d.y(), d.x()) - p.phi))));
        res.range.push_back(m.range);
        res.ids.push_back(m.id);
        res.poses.push_back(p);
    }
    return res;
}

/** Which surveyed landmark explains each label's measurements best (votes by label). */
void bestFitLandmarks(const Residuals& res, std::map<long, Eigen::Vector2d>& lm, MeasurementCalibration& out)
{
    const auto& er = res.er;
    const auto& eb = res.eb;
    const auto& ids = res.ids;
    const auto& poses = res.poses;
    std::map<long, std::map<long, size_t>> votes;
    for (size_t i = 0; i < er.size(); ++i)
    {
        const double r_meas = er[i] + (lm[ids[i]] - Eigen::Vector2d(poses[i].x, poses[i].y)).norm();
        const double b_meas = mrpt::DEG2RAD(eb[i]) +
                              std::atan2(lm[ids[i]].y() - poses[i].y, lm[ids[i]].x() - poses[i].x) -
                              poses[i].phi;
        long best = -1;
        double best_cost = std::numeric_limits<double>::infinity();
        for (const auto& [id, pos] : lm)
        {
            const Eigen::Vector2d d = pos - Eigen::Vector2d(poses[i].x, poses[i].y);
            const double dr = (r_meas - d.norm()) / out.range.mad_std;
            const double db = mrpt::RAD2DEG(mrpt::math::wrapToPi(
                                  b_meas - (std::atan2(d.y(), d.x()) - poses[i].phi))) /
                              out.bearing.mad_std;
            if (dr * dr + db * db < best_cost) best_cost = dr * dr + db * db, best = id;
        }
        votes[ids[i]][best]++;
    }
    for (const auto& [label, v] : votes)
    {
        size_t total = 0;
        std::pair<long, size_t> top{-1, 0};
        for (const auto& [id, n] : v)
        {
            total += n;
            if (n > top.second) top = {id, n};
        }
        out.best_fit_landmark[label] = {top.first, static_cast<double>(top.second) /
                                                       static_cast<double>(total)};
    }
}

/** MAD std of the range residuals by measured range. */
std::map<double, std::pair<size_t, double>> rangeStdByRange(const Residuals& res)
{
    std::map<double, std::pair<size_t, double>> out;
    const double inf = std::numeric_limits<double>::infinity();
    double lo = 0;
    for (double hi : {1.5, 3.0, 4.5, inf})
    {
        std::vector<double> e;
        for (size_t i = 0; i < res.er.size(); ++i)
            if (res.range[i] >= lo && res.range[i] < hi) e.push_back(res.er[i]);
        if (!e.empty()) out[hi] = {e.size(), madStd(e, median(e))};
        lo = hi;
    }
    return out;
}
}  // namespace

hymm::core::OptionTable NoiseCalibrationOptions::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.reals("windows_s", windows_s, "s", above(0, 1e6), 1,
            "window lengths of the odometry fit (rounded to whole ground-truth periods)");
    t.real("fit_min_window_s", fit_min_window_s, "s", atLeast(0, 1e6),
           "the joint fit uses the windows from this length on (<= the longest window)");
    t.real("bias_window_s", bias_window_s, "s", above(0, 1e6),
           "window length of the command scale/offset fit");
    t.real("max_gap_s", max_gap_s, "s", above(0, 1e6), "longer ground-truth steps are gaps");
    t.real("max_speed_mps", max_speed_mps, "m/s", above(0, 1000), "faster ground-truth steps are jumps");
    t.real("max_turn_rate_deg_s", max_turn_rate_deg_s, "deg/s", above(0, 1e5), "faster turns are jumps");
    t.real("outlier_threshold", outlier_threshold, "", above(0, 1e6),
           "gross outlier: |e - median| > this x robust std");
    t.real("max_lag_s", max_lag_s, "s", atLeast(0, 1e6), "command-to-motion delays searched");
    t.real("truth_std_xy_m", truth_std_xy_m, "m", atLeast(-1, 100),
           "ground-truth position noise; negative: estimated from the track");
    t.real("truth_std_phi_deg", truth_std_phi_deg, "deg", atLeast(-1, 180),
           "ground-truth heading noise; negative: estimated from the track");
    return t;
}

void NoiseCalibrationOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                 const std::string& section)
{
    table().load(cfg, section);
    if (fit_min_window_s > *std::max_element(windows_s.begin(), windows_s.end()))
        hymm::core::throwConfigError(section, "fit_min_window_s", std::to_string(fit_min_window_s),
                                     "must not exceed the longest of windows_s");
}

void NoiseCalibrationOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                               const std::string& section) const
{
    auto copy = *this;
    copy.table().save(cfg, section);
}

MeasurementCalibration calibrateMeasurementNoise(
    const std::vector<LandmarkMeasurement>& measurements, const std::vector<StampedPose2D>& truth,
    const std::vector<hymm::io::LandmarkRecord>& landmarks, const NoiseCalibrationOptions& options)
{
    const Track track(truth, options);
    std::map<long, Eigen::Vector2d> lm;
    for (const auto& l : landmarks) lm[l.id] = Eigen::Vector2d(l.x, l.y);
    MeasurementCalibration out;
    const Residuals res = residualsOf(measurements, track, lm, out.skipped);
    const auto& er = res.er;
    const auto& eb = res.eb;
    if (er.empty())
        throw std::invalid_argument(
            "calibrateMeasurementNoise: no measurement of a known landmark inside the ground truth");
    out.range = robustStats(er, options.outlier_threshold);
    out.bearing = robustStats(eb, options.outlier_threshold);
    for (size_t i = 0; i < er.size(); ++i)
    {
        auto& c = out.outliers_by_landmark[res.ids[i]];
        ++c.first;
        const bool out_r = std::abs(er[i] - out.range.median) >
                           options.outlier_threshold * out.range.mad_std;
        const bool out_b = std::abs(eb[i] - out.bearing.median) >
                           options.outlier_threshold * out.bearing.mad_std;
        c.second += (out_r || out_b) ? 1 : 0;
    }
    bestFitLandmarks(res, lm, out);
    out.range_std_by_range = rangeStdByRange(res);
    return out;
}

NoiseCalibrationResult calibrateMrclam(const std::vector<std::string>& inputs, int robot,
                                       const std::string& config_file)
{
    MrclamImporter::Options mo;
    NoiseCalibrationOptions co;
    if (!config_file.empty())
    {
        const auto cfg = hymm::core::openConfigFile(config_file);
        mo.loadFromConfigFile(*cfg, "MrclamImporter");
        co.loadFromConfigFile(*cfg, "NoiseCalibration");
    }
    if (robot < 1 || robot > mo.num_robots)
        throw std::invalid_argument("calibrateMrclam: robot " + std::to_string(robot) +
                                    " is not in 1.." + std::to_string(mo.num_robots));
    mo.robot = robot;
    const auto in = MrclamImporter::findInputs(inputs, robot);
    if (in.groundtruth.empty() || in.landmarks.empty())
        throw std::runtime_error("calibrateMrclam: Robot" + std::to_string(robot) +
                                 "_Groundtruth.dat and Landmark_Groundtruth.dat are required");
    NoiseCalibrationResult res;
    res.reading.format = "mrclam";
    const auto dir = std::filesystem::path(in.odometry).parent_path();
    res.source = (dir.filename().empty() ? dir.string() : dir.filename().string()) + " robot " +
                 std::to_string(robot);
    const MrclamImporter imp(mo);
    const auto controls = imp.readOdometry(in.odometry, res.reading);
    res.reading.odometry_samples = controls.size();
    const auto truth = imp.readGroundTruth(in.groundtruth, res.reading);
    res.reading.ground_truth_poses = truth.size();
    const auto lms = MrclamImporter::readLandmarks(in.landmarks, res.reading);
    res.reading.landmarks = lms.size();
    std::vector<LandmarkMeasurement> meas;
    for (const auto& o : imp.readMeasurements(in.measurements,
                                              imp.barcodeMap(in.barcodes, res.reading),
                                              res.reading))
    {
        const auto& br = dynamic_cast<const mrpt::obs::CObservationBearingRange&>(*o);
        for (const auto& m : br.sensedData)
            meas.push_back({mrpt::Clock::toDouble(br.timestamp), m.landmarkID, m.range, m.yaw});
    }
    res.odometry = calibrateOdometryNoise(controls, truth, co, mo.odometry);
    res.measurements = calibrateMeasurementNoise(meas, truth, lms, co);
    return res;
}

}  // namespace hymm::datasets
