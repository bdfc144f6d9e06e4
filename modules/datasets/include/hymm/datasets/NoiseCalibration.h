/**
 * @file NoiseCalibration.h
 * @brief Calibrates the noise model of a converter (per-sample control noise of the
 *        odometry, range and bearing noise of identified landmark measurements) against
 *        a ground-truth track (UTIAS MRCLAM: Vicon poses and surveyed landmarks).
 *
 * **Odometry.** The converter's model (OdometryIntegrator) adds independent noise of
 * std (std_speed, std_turn_rate) to every control sample and propagates it to first
 * order, so an increment over k samples has covariance
 *     Sigma = std_speed^2 * A + std_turn_rate^2 * B,
 * A and B being the propagated covariances for unit variances (both grow with k: the
 * heading variance linearly, the lateral one with k^3). The track is cut into
 * non-overlapping windows of each configured length; in each window the commanded
 * motion is integrated exactly as the converter does, and the residual is the
 * ground-truth relative pose (pose at the window end in the frame of the pose at its
 * start) minus the integrated increment. The two variances are the maximum-likelihood
 * estimate over the windows, r_j ~ N(0, s1 A_j + s2 B_j + V_j) with V_j the ground
 * truth's own noise (estimated from second differences of the track), found by Fisher
 * scoring (the Newton step of variance-component models). This is done for each window
 * length alone (if the per-sample model holds, the estimates do not depend on the
 * length) and for the lengths from `fit_min_window_s` on together (the values for the
 * converter config: the drift rate of the random walk, which sets the filter's
 * uncertainty over a run; errors that cancel within a second, such as a command delay,
 * would otherwise inflate it), and the joint values' predictions are compared with
 * every length.
 * The growth check: the mean squared heading residual against the window length on
 * log-log axes has slope 1 for the per-sample (random-walk) model and 2 for a
 * systematic error. A scale and an offset of the commands are fitted too (least
 * squares over windows), and the delay between commands and motion (reported, not
 * applied).
 *
 * **Measurements.** Each measurement's range and bearing are predicted from the
 * ground-truth pose interpolated at its time and the surveyed landmark; the residuals'
 * centre is their median and their spread the MAD scaled to a Gaussian std
 * (1.4826 * median |e - median|). Residuals farther than `outlier_threshold` robust stds
 * from the median are gross outliers (counted, left out of the inlier mean/std). The
 * converter's model has no bias term, so the value proposed for its config is the
 * robust RMS about zero, sqrt(median^2 + MAD-std^2). For each landmark label the
 * surveyed landmark its measurements fit best is reported (mislabelled barcodes).
 *
 * **Quirks.** Ground-truth gaps (time steps above `max_gap_s`) and jumps (implied speed
 * or turn rate above the limits) break the track: windows and measurements that need
 * such a step are skipped and counted, as are windows not covered by control samples.
 */
#pragma once

#include <hymm/core/OptionTable.h>

#include <hymm/io/trajectory_io.h>
#include <mrpt/config/CLoadableOptions.h>

#include <map>
#include <string>
#include <vector>

#include "hymm/datasets/ImportSummary.h"
#include "hymm/datasets/OdometryIntegrator.h"

namespace hymm::datasets
{
struct NoiseCalibrationOptions : public mrpt::config::CLoadableOptions
{
    /** Window lengths of the odometry fit [s]; each is rounded to a whole number of
     *  ground-truth periods. */
    std::vector<double> windows_s = {0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0};
    /** The joint fit (the values for the config) uses the window lengths from this on
     *  [s]: the per-sample model is a random walk, and errors that cancel within a
     *  second (a command delay) must not set the drift rate (see the growth check). */
    double fit_min_window_s = 5.0;
    /** Window length of the command scale/offset fit [s]. */
    double bias_window_s = 1.0;
    double max_gap_s = 0.05;                   //!< longer ground-truth steps are gaps [s]
    double max_speed_mps = 2.0;                //!< faster ground-truth steps are jumps [m/s]
    double max_turn_rate_deg_s = 360.0;        //!< faster turns are jumps [deg/s]
    double outlier_threshold = 5.0;            //!< gross outlier: |e - median| > this * robust std
    double max_lag_s = 0.5;                    //!< command-to-motion delays searched [s]
    /** Noise of the ground-truth poses, position [m] and heading [deg]; negative:
     *  estimated from second differences of the track (which also holds any real
     *  50 Hz motion jitter, so it errs on the large side). */
    double truth_std_xy_m = -1;
    double truth_std_phi_deg = -1;

    /** Every ini key, declared once: loader, saver and README table come from it. */
    hymm::core::OptionTable table();
    /** Reads [section] (all keys optional; unknown keys are errors). */
    void loadFromConfigFile(
        const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(
        mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
};

/** Maximum-likelihood control noise from the windows of one length (or all). */
struct OdometryNoiseFit
{
    double window_s = 0;             //!< window length [s] (0: all lengths together)
    size_t windows = 0;              //!< windows used
    double std_speed_mps = 0;        //!< per-sample speed noise [m/s]
    double std_turn_rate_deg_s = 0;  //!< per-sample turn-rate noise [deg/s]
    double se_speed_mps = 0;         //!< standard error of std_speed_mps (Fisher information)
    double se_turn_rate_deg_s = 0;   //!< standard error of std_turn_rate_deg_s
    size_t iterations = 0;           //!< Fisher-scoring iterations
    double mean_nees = 0;            //!< mean r' Sigma^-1 r with the fitted values (3 if Gaussian)
    double inside_95 = 0;            //!< fraction of windows with NEES below chi2_3(0.95)
    double mean_nees_joint = 0;      //!< mean NEES of these windows with the joint fit
    double heading_ms_deg2 = 0;      //!< mean squared heading residual [deg^2]
    double heading_model_deg2 = 0;   //!< its prediction by the joint fit [deg^2]
    double position_ms_m2 = 0;       //!< mean squared position residual [m^2]
    double position_model_m2 = 0;    //!< its prediction by the joint fit [m^2]
};

/** Systematic command errors over windows of one length: the delay of the motion after
 *  the commands, then truth = scale * commanded + offset * T for the delayed commands. */
struct OdometryBiasFit
{
    double window_s = 0;
    size_t windows = 0;
    /** Delay [s]: the shift of the control times (whole truth periods within
     *  +-max_lag_s) that minimises the mean squared heading residual. */
    double lag_s = 0;
    double turn_raw_std_deg = 0;       //!< heading residual RMS, commands as logged [deg]
    double lag_heading_std_deg = 0;    //!< heading residual RMS, commands delayed [deg]
    double speed_scale = 1, speed_offset_mps = 0;        //!< on the distance travelled
    double turn_scale = 1, turn_offset_deg_s = 0;        //!< on the heading change
    double turn_residual_std_deg = 0;  //!< heading residual RMS after delay, scale, offset [deg]
};

struct OdometryCalibration
{
    std::vector<OdometryNoiseFit> per_window;  //!< one per configured window length
    OdometryNoiseFit joint;  //!< window lengths >= fit_min_window_s together (window_s = 0)
    double fit_min_window_s = 0;  //!< the option the joint fit used [s]
    OdometryBiasFit bias;
    /** Slope of log(mean squared heading residual) against log(window length) over
     *  the per-window fits: 1 for the per-sample model, 2 for a systematic error. */
    double heading_growth_exponent = 0;
    double truth_std_xy_m = 0;      //!< ground-truth position noise (second differences)
    double truth_std_phi_deg = 0;   //!< ground-truth heading noise [deg]
    size_t truth_poses = 0;
    size_t truth_breaks = 0;        //!< steps of the track that are gaps or jumps
    std::map<std::string, size_t> skipped;  //!< windows left out, by reason
};

/** Robust statistics of one residual (range [m] or bearing [deg]). */
struct ResidualStats
{
    size_t used = 0;          //!< residuals (outliers included)
    size_t outliers = 0;      //!< beyond outlier_threshold robust stds from the median
    double median = 0;        //!< robust centre (bias)
    double mad_std = 0;       //!< 1.4826 * MAD: robust std about the median
    double inlier_mean = 0;   //!< mean of the inliers
    double inlier_std = 0;    //!< std of the inliers
    double model_std = 0;     //!< sqrt(median^2 + mad_std^2): zero-mean std for the config
    double p01 = 0, p99 = 0;  //!< 1 % and 99 % quantiles (the tails the std does not show)
};

struct LandmarkMeasurement
{
    double t = 0;        //!< [s]
    long id = -1;        //!< landmark id (MRCLAM subject)
    double range = 0;    //!< [m]
    double bearing = 0;  //!< [rad], counter-clockwise from the forward axis
};

struct MeasurementCalibration
{
    ResidualStats range;      //!< [m]
    ResidualStats bearing;    //!< [deg]
    /** Robust range std per range interval: upper bound [m] -> (count, MAD std [m]). */
    std::map<double, std::pair<size_t, double>> range_std_by_range;
    /** Per landmark id: (measurements, gross outliers in range or bearing). */
    std::map<long, std::pair<size_t, size_t>> outliers_by_landmark;
    /** Per landmark id: the surveyed landmark that most of its measurements fit best
     *  (smallest residual normalised by the robust stds) and the fraction that do; a
     *  label whose measurements fit another landmark points to a mislabelled barcode. */
    std::map<long, std::pair<long, double>> best_fit_landmark;
    std::map<std::string, size_t> skipped;  //!< measurements left out, by reason
};

struct NoiseCalibrationResult
{
    std::string source;                //!< what was calibrated (for the report)
    ImportSummary reading;             //!< skips/repairs while reading the files
    OdometryCalibration odometry;
    MeasurementCalibration measurements;

    /** Multi-line human-readable report: every fit, the growth check, the bias. */
    std::string toString() const;
    /** The calibrated keys of the converter's section, ready to paste into an .ini. */
    std::string iniLines() const;
};

/**
 * Fits the per-sample control noise of the unicycle (v, omega) model of the converter.
 * `controls` as OdometryIntegrator takes them; `truth` the ground-truth poses, strictly
 * increasing in time (throws std::invalid_argument otherwise, or if no window can be
 * used). Of `model` only max_hold_s is used (the noise values are what is fitted), so
 * the windows are integrated exactly as the converter integrates its frames.
 */
OdometryCalibration calibrateOdometryNoise(
    const std::vector<OdometryIntegrator::ControlSample>& controls,
    const std::vector<hymm::io::StampedPose2D>& truth, const NoiseCalibrationOptions& options,
    const OdometryIntegrator::Options& model = {});

/**
 * Range and bearing residuals of `measurements` against `truth` (interpolated at each
 * measurement time) and `landmarks` (by id). Measurements of unknown landmarks or
 * outside / across a break of the track are skipped and counted. Throws
 * std::invalid_argument if none is left.
 */
MeasurementCalibration calibrateMeasurementNoise(
    const std::vector<LandmarkMeasurement>& measurements,
    const std::vector<hymm::io::StampedPose2D>& truth,
    const std::vector<hymm::io::LandmarkRecord>& landmarks,
    const NoiseCalibrationOptions& options);

/**
 * Calibrates the MRCLAM converter on robot `robot` of the dataset folder(s) `inputs`,
 * reading the files as `hymm-import --format mrclam` does. `config_file` (may be "")
 * supplies [MrclamImporter] (its `robot` key is overridden by `robot`) and
 * [NoiseCalibration] (NoiseCalibrationOptions).
 */
NoiseCalibrationResult calibrateMrclam(const std::vector<std::string>& inputs, int robot,
                                       const std::string& config_file);

}  // namespace hymm::datasets
