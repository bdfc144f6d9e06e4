/**
 * @file ScanOdometry.h
 * @brief Scan-matching odometry: the vehicle's motion between two consecutive laser
 *        scans, measured by aligning the previous scan to the current one with one of
 *        the Scan-SLAM matchers, fused with the wheel odometry of the same interval.
 *
 * Where landmarks are seldom in view (corridors, a poor wheel odometry, Intel's lab) the
 * prediction grows until no template is located locally and every loop-closing window is
 * too wide. Two consecutive scans overlap almost entirely, so their alignment measures
 * the motion in between far better than the wheels do. Both are Gaussian measurements of
 * one SE(2) increment u (the pose at the current scan in the vehicle frame of the
 * previous one): the fusion is a Kalman update of the wheel's (u_w, P_w) by the scan's
 * (u_s, P_s), with an NN gate on their difference, so a failed alignment (a featureless
 * corridor, people in the way) leaves the wheel odometry as it was.
 *
 * The scan is then used twice: here and by the landmark sources. Its noise is averaged
 * over hundreds of returns here, so the correlation it leaves between the two uses is
 * small; the floors (min_std_*) and the growth with the distance travelled keep P_s
 * honest (see the README for the measured NEES).
 *
 * Ini sections: [ScanOdometry] (Options) and [ScanOdometryMatcher] (the chosen matcher's
 * keys, as in [IcpMatcher] / [SogMatcher] / [CorrelativeMatcher]); the return noise is
 * [Laser]'s.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hymm/scanslam/PointSet.h"
#include "hymm/scanslam/ScanMatcher.h"

namespace hymm::scanslam
{
class ScanOdometry
{
public:
    struct Options
    {
        bool enabled = false;
        std::string matcher = "correlative";  //!< sog | icp | correlative (keys in [ScanOdometryMatcher])
        ScanNoise noise{};            //!< return noise ([Laser])
        double max_range_m = 30;      //!< returns farther away are not aligned [m]
        size_t max_points = 300;      //!< the previous scan is thinned evenly to this many points
        double gate_prob = 0.999;     //!< chi-square(3) gate on scan - wheel increment (0 or 1: none)
        /** The matcher's covariance of a consecutive pair times this (measured: README),
         *  on top of the matcher's own cov_inflation, which was measured on templates. */
        double cov_scale = 3.5;
        double min_std_xy_m = 0.01;   //!< std added to the aligned increment, x and y [m]
        double min_std_phi = 0.1 * M_PI / 180;  //!< and to its angle [rad] (ini: min_std_phi_deg)
        double std_xy_per_m = 0;      //!< std added per metre travelled (unmodelled errors)
        double std_phi_per_m = 0;     //!< [rad/m] (ini: std_phi_deg_per_m)
        /** Keyframes: each scan is aligned to the last keyframe scan, not to the previous
         *  scan, until the vehicle is this far from the keyframe's pose (0: every scan is
         *  the next one's reference). The pose relative to the keyframe is filtered from
         *  the wheels and every alignment to it, so within a keyframe neither the
         *  alignment errors nor the wheels' add up step by step. [m] */
        double keyframe_distance_m = 0;
        double keyframe_angle = 30 * M_PI / 180;  //!< or has turned this much [rad] (ini: keyframe_angle_deg)
        /** The covariance of every fused increment handed to the filter times this.
         *  Consecutive increments share a scan (with keyframes, the keyframe's alignment
         *  too), so their errors partly cancel over a drive, which a filter taking each
         *  step as independent counts in full. The right value depends on the scene
         *  (measured 0.7 on one simulated world, 1 on another): calibrate it against
         *  ground truth (README, "Covariance of the steps"). */
        double step_cov_scale = 1;
        /** The covariance handed to the filter for a step inside a keyframe (not the
         *  first after it): `alignment`, the alignment's as if it measured that step alone
         *  (the steps of one keyframe then count its shared error once each), or `growth`,
         *  the growth of the keyframe-relative pose's covariance over the step, so that the
         *  steps of a keyframe add up to the covariance of the pose relative to it. */
        enum class KeyframeStepCov
        {
            alignment,
            growth
        };
        KeyframeStepCov keyframe_step_cov = KeyframeStepCov::alignment;
        /** The alignment's heading variance times this, on top of cov_scale (the matchers'
         *  covariance shape was measured heading-light on consecutive scans: README). */
        double heading_cov_scale = 1;
        /** Estimate the wheels' systematic turn per metre travelled (unequal wheel radii:
         *  the heading error grows with the distance, not with the time or the turning)
         *  from the alignments, and remove it from every wheel increment before it is
         *  used (README, "The wheels' turn bias"). */
        bool wheel_turn_bias = false;
        double wheel_turn_bias_prior = 5 * M_PI / 180;  //!< prior std of that bias [rad/m] (ini: wheel_turn_bias_prior_deg_per_m)
        /** Its random walk: std of its change per square root of a metre travelled
         *  [rad/m/sqrt(m)] (ini: wheel_turn_bias_walk_deg_per_m) */
        double wheel_turn_bias_walk = 0.01 * M_PI / 180;
        /** The estimate corrects the wheels only while it is this many of its std from
         *  zero: an estimate of a bias that is not there would turn every increment the
         *  same wrong way, an error the EKF takes for independent noise. */
        double wheel_turn_bias_min_sigmas = 3;

        /** Every key, declared once (loader, unknown-key check, saver, README table). */
        core::OptionTable table();
        /** Reads [section] and [Laser]'s noise; unknown keys and bad values throw. */
        void load(const mrpt::config::CConfigFileBase& cfg, const std::string& section);
    };

    /** Counters of a run, by outcome. */
    struct Stats
    {
        size_t scans = 0;          //!< scans given to refine()
        size_t no_reference = 0;   //!< no previous scan (the first one, or after reset())
        size_t too_few_points = 0; //!< fewer than 3 usable returns in either scan or seen again (or a non-finite wheel increment)
        std::map<std::string, size_t> align_failed;  //!< by the matcher's failure reason
        size_t gated = 0;          //!< aligned, but too far from the wheel increment
        size_t fused = 0;          //!< the aligned increment fused with the wheel's
        size_t keyframes = 0;      //!< scans that became the reference (every scan without keyframes)
        size_t bias_updates = 0;   //!< keyframes whose last alignment updated the wheels' turn bias
        size_t bias_gated = 0;     //!< and those whose turn disagreed with the bias estimate (chi-square(1), gate_prob)
        size_t bias_applied = 0;   //!< wheel increments corrected by the estimate
        size_t growth_clamped = 0; //!< keyframe steps whose covariance growth had a negative eigenvalue

        /** (name, count) of every counter, failures as align_failed.<reason>. */
        std::vector<std::pair<std::string, size_t>> list() const;
    };

    /** An SE(2) increment with its covariance. */
    struct Increment
    {
        Vec3 mean = Vec3::Zero();
        Mat3 cov = Mat3::Zero();
    };

    /** [ScanOdometry] and [ScanOdometryMatcher] of `cfg` (defaults when null); the
     *  matcher's section is read even when disabled, so a strict file knows it. */
    static Options loadOptions(const mrpt::config::CConfigFileBase* cfg);
    static std::unique_ptr<ScanOdometry> make(const Options& options, const mrpt::config::CConfigFileBase* cfg);
    /** The matcher `kind` with the keys of [ScanOdometryMatcher]; the correlative one
     *  starts from consecutive-scan defaults (0.1 m grid, +-0.4 m and +-4 deg window). */
    static std::unique_ptr<ScanMatcher> odometryMatcher(const std::string& kind,
                                                        const mrpt::config::CConfigFileBase* cfg);

    ScanOdometry(const Options& options, std::unique_ptr<ScanMatcher> matcher);

    /** The vehicle's increment from the previous scan given here to `scan`: `wheel`
     *  (the wheel odometry of that interval, with its covariance) fused with the
     *  alignment of the reference scan to this one, or `wheel` itself when there is no
     *  reference, the alignment fails or is gated. The reference is the previous scan,
     *  or with keyframe_distance_m > 0 the keyframe: the alignment then measures the pose
     *  relative to the keyframe, which updates the filtered relative pose (predicted by
     *  the wheels), and the increment's mean is the step of that pose's estimate; its
     *  covariance is the one of the wheels fused with the alignment seen as a measurement
     *  of this step alone (as without keyframes), or with keyframe_step_cov = growth the
     *  growth of the relative pose's covariance over the step. `scan` becomes the next reference
     *  when it starts a keyframe (always without keyframes, and after a failed or gated
     *  alignment). Never throws on bad data; the result's covariance is symmetric PSD. */
    Increment refine(const mrpt::obs::CObservation2DRangeScan& scan, const Increment& wheel);

    /** Forgets the previous scan (the next refine() has nothing to align to): a motion
     *  the reference does not cover was applied in between. */
    void reset();

    /** The estimated turn of the wheels per metre travelled (true heading change minus
     *  the wheels', per metre) and its std [rad/m]; 0 and the prior without
     *  wheel_turn_bias. */
    double wheelTurnBias() const { return turn_bias_; }
    double wheelTurnBiasStd() const { return std::sqrt(turn_bias_var_); }
    /** Whether the estimate is applied to the wheels now (wheel_turn_bias_min_sigmas). */
    bool wheelTurnBiasApplied() const;

    /** The last refine()'s alignment as a measurement of the vehicle's pose relative to
     *  its pose at the reference scan (none when it failed, was gated or had no
     *  reference): for a filter that keeps a copy of the pose at the reference
     *  (EkfSlam::updateVehicleFromCopy) instead of taking refine()'s increment. */
    const std::optional<Increment>& lastRelativeMeasurement() const { return last_relative_; }
    /** The vehicle at the last scan relative to its pose at the reference scan, filtered
     *  from the wheels and the alignments to the reference (zero after a new reference). */
    const Increment& relativePose() const { return since_reference_; }
    /** Whether the last refine()'s scan became the reference of the next ones. */
    bool lastScanIsReference() const { return last_is_reference_; }

    const Stats& stats() const { return stats_; }
    const Options& options() const { return options_; }

    /** Saved run state (hymm-slam --save-state / --resume): the reference scan, the
     *  filtered pose since it, the wheels since it, the turn bias with its pending
     *  observation and the counters, bit for bit, so a resumed run fuses the steps the
     *  uninterrupted one would. The matchers keep nothing between alignments. loadState()
     *  expects the same options and throws std::runtime_error on a corrupt state.
     *  Source: ScanLandmarkState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

private:
    /** The vehicle increment of the alignment `r` (u = increment(z)) with its covariance:
     *  the matcher's through the numeric Jacobian of `increment`, times cov_scale, plus
     *  the floors and the per-metre terms. */
    Increment alignedIncrement(const AlignResult& r, const std::function<Vec3(const Vec3&)>& increment) const;
    /** The covariance of the step `step` from the relative pose `before` that makes the
     *  composition of the steps handed on since the reference hold `after`, the relative
     *  pose's covariance now (keyframe_step_cov = growth), PSD-clamped; `fallback` when it
     *  cannot be formed. Updates handed_cov_. */
    Mat3 covarianceGrowth(const Increment& before, const Mat3& after, const Vec3& step, const Mat3& fallback);
    /** Valid returns of `scan` within max_range_m, in the sensor frame. */
    PointSet usablePoints(const mrpt::obs::CObservation2DRangeScan& scan) const;
    /** `wheel` less the estimated turn bias while it is applied (else itself). */
    Increment unbiasedWheel(const Increment& wheel);
    /** Adds `wheel_read` (the wheels as read) to their motion since the reference and,
     *  when the scan was aligned (`relative`, the pose relative to the reference it
     *  measured), keeps the turn observation of that alignment. */
    void observeTurn(const Increment& wheel_read, const std::optional<Increment>& relative);
    /** The Kalman update of the turn bias by the last alignment to the reference (if any),
     *  then forgets it: called when the reference is left. */
    void updateTurnBias();
    /** The increment of `wheel` fused with the alignment of the reference to `scan`
     *  (`current`: its usable returns), or `wheel`; when fused, `relative_measured` gets
     *  the alignment as a measurement of the pose relative to the reference. */
    Increment aligned(const mrpt::obs::CObservation2DRangeScan& scan, const PointSet& current, const Vec3& mount,
                      const Increment& wheel, std::optional<Increment>& relative_measured);

    Options options_;
    std::unique_ptr<ScanMatcher> matcher_;
    Stats stats_;
    bool has_reference_ = false;
    PointSet reference_;               //!< the reference (keyframe) scan, thinned (its sensor frame)
    Vec3 reference_mount_ = Vec3::Zero();  //!< its sensor pose on the vehicle
    /** The vehicle at the previous scan relative to its pose at the reference scan, with
     *  its covariance: a three-state filter of the wheels and the alignments to the
     *  keyframe (zero right after a new reference). */
    Increment since_reference_;
    bool reference_is_previous_ = false;  //!< the reference is the previous scan (set there)
    /** The covariance of the steps handed on since the reference, composed as the filter
     *  composes them (keyframe_step_cov = growth): at least since_reference_'s. */
    Mat3 handed_cov_ = Mat3::Zero();
    /** The wheels alone (as read, bias included) since the reference scan, and the
     *  distance they travelled [m]. */
    Increment wheel_since_reference_;
    double wheel_distance_since_reference_ = 0;
    /** The last fused alignment's measurement of the turn bias: its heading relative to
     *  the reference minus the wheels' (e = b ds + noise of variance var). */
    struct TurnObservation
    {
        double e = 0, ds = 0, var = 0;
    };
    std::optional<TurnObservation> turn_observation_;
    std::optional<Increment> last_relative_;  //!< lastRelativeMeasurement()
    bool last_is_reference_ = false;          //!< lastScanIsReference()
    double turn_bias_ = 0;      //!< [rad/m]
    double turn_bias_var_ = 0;  //!< [rad^2/m^2] (the prior's, set by the constructor)
};

/** a (+) b with the covariance of both propagated to first order (independent a and b). */
ScanOdometry::Increment composeIncrements(const ScanOdometry::Increment& a, const ScanOdometry::Increment& b);

/** An increment in a saved run state (mean, covariance); loading throws
 *  std::runtime_error naming `what` on a corrupt or non-finite one. */
void saveIncrement(mrpt::serialization::CArchive& out, const ScanOdometry::Increment& i);
ScanOdometry::Increment loadIncrement(mrpt::serialization::CArchive& in, const char* what);

/** The wheel increment `w` updated by the independent measurement `s` of the same
 *  increment (Kalman update, Joseph form); `d2` receives the squared Mahalanobis
 *  distance of s - w (angle wrapped) under P_w + P_s. */
ScanOdometry::Increment fuseIncrements(const ScanOdometry::Increment& w, const ScanOdometry::Increment& s,
                                       double* d2 = nullptr);

}  // namespace hymm::scanslam
