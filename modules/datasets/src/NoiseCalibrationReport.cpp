/**
 * @file NoiseCalibrationReport.cpp
 * @brief The noise calibration as text: the report of every fit and the config lines.
 */
#include "hymm/datasets/NoiseCalibration.h"

#include <iomanip>
#include <ostream>
#include <sstream>

namespace hymm::datasets
{
namespace
{
/** " key=count" pairs of a skip / repair tally, " none" when empty. */
void writeCounts(std::ostream& s, const std::map<std::string, size_t>& m)
{
    if (m.empty()) s << " none";
    for (const auto& [k, v] : m) s << " " << k << "=" << v;
    s << "\n";
}

/** One row of the odometry fit table. */
void writeFit(std::ostream& s, const OdometryNoiseFit& f)
{
    s << std::setprecision(3) << "  " << std::setw(8) << f.window_s << std::setw(8)
      << f.windows << std::setprecision(4) << std::setw(10) << f.std_speed_mps << " ("
      << f.se_speed_mps << ")" << std::setw(10) << f.std_turn_rate_deg_s << " ("
      << f.se_turn_rate_deg_s << ")" << std::setprecision(2) << std::setw(8) << f.mean_nees
      << std::setw(6) << 100 * f.inside_95 << "% | " << f.mean_nees_joint << " "
      << std::setprecision(4) << f.heading_ms_deg2 << "/" << f.heading_model_deg2 << " "
      << std::setprecision(6) << f.position_ms_m2 << "/" << f.position_model_m2 << "\n";
}

/** One line of robust residual statistics. */
void writeStats(std::ostream& s, const char* what, const ResidualStats& r, const char* unit)
{
    s << std::setprecision(4) << what << ": " << r.used << " residuals, median " << r.median
      << " " << unit << ", MAD std " << r.mad_std << " " << unit << ", " << r.outliers
      << " gross outliers; 1%/99% quantiles " << r.p01 << "/" << r.p99 << " " << unit
      << "; inliers mean " << r.inlier_mean << " std " << r.inlier_std
      << "; zero-mean std sqrt(median^2+MAD^2) = " << r.model_std << " " << unit << "\n";
}

/** Ground truth, the odometry fits, the growth check and the command bias. */
void writeOdometry(std::ostream& s, const OdometryCalibration& o)
{
    s << std::setprecision(5) << "ground truth: " << o.truth_breaks << " breaks (gaps/jumps) in "
      << o.truth_poses << " poses; noise from second differences: " << o.truth_std_xy_m
      << " m, " << o.truth_std_phi_deg << " deg\n";
    s << "odometry windows skipped:";
    writeCounts(s, o.skipped);
    s << "odometry noise, maximum likelihood per window length (per-sample model):\n"
      << "  window_s windows std_speed_mps (se) std_turn_rate_deg_s (se) mean_NEES in95 | "
         "joint: mean_NEES heading_ms/model_deg2 position_ms/model_m2\n";
    for (const auto& f : o.per_window) writeFit(s, f);
    s << "  joint (windows from " << std::setprecision(3) << o.fit_min_window_s
      << " s on: the values for the config):\n";
    writeFit(s, o.joint);
    s << std::setprecision(2) << "heading growth exponent (log mean squared heading residual vs "
      << "log window): " << o.heading_growth_exponent
      << " (1: per-sample random walk, 2: systematic)\n";
    s << std::setprecision(4) << "command-to-motion delay: " << o.bias.lag_s
      << " s (heading residual RMS over " << o.bias.window_s << " s windows "
      << o.bias.turn_raw_std_deg << " deg -> " << o.bias.lag_heading_std_deg
      << " deg with the controls delayed by it)\n"
      << "delayed commands, scale/offset over " << o.bias.windows << " windows: distance = "
      << o.bias.speed_scale << " * commanded + " << o.bias.speed_offset_mps
      << " m/s * T; heading = " << o.bias.turn_scale << " * commanded + "
      << o.bias.turn_offset_deg_s << " deg/s * T (heading residual RMS -> "
      << o.bias.turn_residual_std_deg << " deg after the fit)\n";
}

/** The residual statistics of the measurements, by range and by landmark. */
void writeMeasurements(std::ostream& s, const MeasurementCalibration& m)
{
    s << "measurements skipped:";
    writeCounts(s, m.skipped);
    writeStats(s, "range", m.range, "m");
    writeStats(s, "bearing", m.bearing, "deg");
    s << "range MAD std by measured range:";
    double lo = 0;
    for (const auto& [hi, v] : m.range_std_by_range)
    {
        s << " [" << std::setprecision(1) << lo << "," << hi << ") m: " << std::setprecision(4)
          << v.second << " m (" << v.first << ");";
        lo = hi;
    }
    s << "\ngross outliers (range or bearing) by landmark id:";
    for (const auto& [id, c] : m.outliers_by_landmark)
        s << " " << id << ": " << c.second << "/" << c.first << ";";
    s << "\nlabels whose measurements fit another surveyed landmark best:";
    size_t mislabelled = 0;
    for (const auto& [label, best] : m.best_fit_landmark)
        if (best.first != label)
            s << " " << label << " -> " << best.first << " (" << std::setprecision(0)
              << 100 * best.second << "% of its measurements);", ++mislabelled;
    if (mislabelled == 0) s << " none";
    s << "\n";
}
}  // namespace

std::string NoiseCalibrationResult::iniLines() const
{
    std::ostringstream s;
    s << std::setprecision(3);
    s << "std_speed_mps = " << odometry.joint.std_speed_mps << "\n"
      << "std_turn_rate_deg_s = " << odometry.joint.std_turn_rate_deg_s << "\n"
      << "std_range_m = " << measurements.range.model_std << "\n"
      << "std_bearing_deg = " << measurements.bearing.model_std << "\n";
    return s.str();
}

std::string NoiseCalibrationResult::toString() const
{
    std::ostringstream s;
    s << std::fixed;
    s << "noise calibration on " << source << "\n"
      << "reading: " << reading.odometry_samples << " control samples, "
      << reading.ground_truth_poses << " ground-truth poses, " << reading.measurements
      << " measurements, " << reading.landmarks << " landmarks\n  skipped:";
    writeCounts(s, reading.skipped);
    s << "  repaired:";
    writeCounts(s, reading.repaired);
    writeOdometry(s, odometry);
    writeMeasurements(s, measurements);
    return s.str();
}

}  // namespace hymm::datasets
