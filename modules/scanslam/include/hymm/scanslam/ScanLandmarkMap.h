/**
 * @file ScanLandmarkMap.h
 * @brief The Scan-SLAM step of one scan (thesis 5.2, 5.5, 5.7) on an EKF with 3-DOF pose
 *        landmarks: every template is predicted into the sensor frame, observed by scan
 *        alignment when more than `in_view_fraction` of its points are in view, and fused
 *        after an NN gate; the returns no template explains are segmented, and segments
 *        that pass the acceptance self-test become new pose landmarks with their template.
 *
 * The templates live here, outside the state vector; the EKF holds only their frames'
 * poses (ekf::EkfSlam::addPoseLandmark / updatePoseLandmark). Every skip and reject is
 * counted by reason (Stats); nothing on bad data throws or puts a NaN in the state.
 *
 * Ini sections: [ScanLandmarks] (this class), [ScanSegmentation] (Segmenter),
 * [ScanAcceptance] (SegmentAcceptance) and the section of the chosen matcher
 * ([SogMatcher], [IcpMatcher] or [CorrelativeMatcher]). Key table in the module README.
 */
#pragma once

#include <hymm/ekf/EkfSlam.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "hymm/scanslam/RevisitLog.h"
#include "hymm/scanslam/ScanMatcher.h"
#include "hymm/scanslam/ScanTemplate.h"
#include "hymm/scanslam/SegmentAcceptance.h"
#include "hymm/scanslam/Segmenter.h"
#include "hymm/scanslam/WideSearch.h"

namespace hymm::scanslam
{
class ScanLandmarkMap
{
public:
    /** Cap of the view_corr_share factor on R: a viewpoint seen again exactly (delta = 0)
     *  has an infinite one. */
    static constexpr double kMaxViewCorrFactor = 1000;

    struct Options
    {
        std::string matcher = "sog";       //!< sog | icp | correlative
        ScanNoise noise{};                 //!< laser noise of the template points (ini: std_range_m, std_bearing_deg)
        double in_view_fraction = 0.9;     //!< thesis 5.7: > 90 % of the points in view
        double gate_prob = 0.99;           //!< NN gate on the aligned observation (5.5)
        /** EkfSlam::updatePoseLandmark's max_iterations for local alignments: > 1
         *  relinearises the update at its own result (iterated EKF); 1 = the EKF. */
        int update_iterations = 1;
        int wide_update_iterations = 10;   //!< the same for the wide-search (loop-closing) updates
        /** A landmark aligned in this scan and another whose template, both placed at the
         *  filter's estimates, overlaps it (this share of the smaller one's points within
         *  explain_distance_m of the other's) are one object: the newer template is
         *  aligned with the older, the relative pose fused (EkfSlam::updateRelativePose,
         *  iterated as the wide-search updates) and the newer removed (mergeDuplicates). */
        bool merge_duplicates = false;
        double merge_min_overlap = 0.5;
        /** A pair whose templates did not align, or whose relative pose was gated, is
         *  tried again after this many scans. */
        size_t merge_retry_scans = 50;
        /** [m] a return within this of a predicted (or aligned) template point is that
         *  landmark's: it creates no new landmark. */
        double explain_distance_m = 1.0;
        double max_creation_range_m = 25;  //!< segments whose centroid is farther are not used [m]
        /** Smallest/largest standard deviation of a segment's points: below this it is a
         *  straight line whose orientation along itself is unobservable (collinear). */
        double min_spread_ratio = 0.05;
        uint32_t seed = 1;                 //!< of the acceptance self-test's perturbations
        /** false: only the templates already held (and those added with
         *  addTemplateLandmark) are observed; no segment becomes a landmark (the
         *  high-level landmarks of thesis 6.1 use the map this way). */
        bool create_landmarks = true;
        /** > 0: only the template points visible from the predicted pose (visiblePart,
         *  bearing bins of this size) are aligned; 0: the whole template. Templates from
         *  one scan are all visible from near where they were made; templates from many
         *  vantage points (high-level landmarks) are not. (ini: visible_bin_deg) */
        double visible_bin = 0;
        double visible_depth_tol_m = 0.3;  //!< depth tolerance of visiblePart [m]
        /** Viewpoint model of the alignment covariance (measured, see the README):
         *  R = R_matcher + diag(s_xy^2, s_xy^2, s_phi^2) with s = floor + rate * d, d the
         *  distance between the template frame's position in the sensor frame now
         *  (predicted) and when it was made. The matcher's covariance holds the sensor
         *  noise only; a template re-observed from elsewhere meets another sampling of
         *  the object, other segment ends and occlusions, whose error grows with d. */
        double view_std_xy_m = 0;        //!< floor of s_xy [m] (ini: view_std_xy_m)
        double view_std_xy_per_m = 0;    //!< growth of s_xy per metre of d (ini: view_std_xy_per_m)
        double view_std_phi = 0;         //!< floor of s_phi [rad] (ini: view_std_phi_deg)
        double view_std_phi_per_m = 0;   //!< growth of s_phi per metre of d [rad/m] (ini: view_std_phi_deg_per_m)
        /** Correlation of a template's alignment errors between viewpoints (measured, see
         *  the README, "Correlated re-observations"): the errors of two alignments of one
         *  template from viewpoints delta apart (the sensor's position in the template
         *  frame) correlate as about c exp(-delta / L). The EKF takes every alignment as
         *  independent. With c > 0 a local alignment whose nearest earlier fused viewpoint
         *  of the same template is delta away has its R multiplied by 1 + c (f - 1),
         *  f = (1 + rho) / (1 - rho), rho = exp(-delta / L): f is the long-run variance
         *  factor of an AR(1) sequence, so a run of alignments carries about one correlated
         *  error per 2 L of viewpoints, and a revisited viewpoint adds little. The wide
         *  search's (loop-closing) answers keep their R. 0: off (every alignment
         *  independent). */
        double view_corr_share = 0;      //!< c (ini: view_corr_share)
        double view_corr_length_m = 7;   //!< L [m] (ini: view_corr_length_m)
        /** How view_corr_share > 0 is modelled. `inflate`: R scaled as above.
         *  `state`: the correlated share is a state, the template's apparent pose
         *  A = L + b (an auxiliary EKF block, EkfSlam::addBlockCopy) whose error b about
         *  the template's pose L is a first-order Gauss-Markov process over the viewpoint:
         *  between two alignments delta apart, b <- rho b + w, rho = exp(-delta / L),
         *  var(w) = (1 - rho^2) c R (R in the global frame: the world orientation of the
         *  alignment's R). A local alignment observes A with (1 - c) R, so successive
         *  alignments keep the precise differences that tell the vehicle's motion while
         *  the template's pose learns one correlated error per correlation length. A
         *  template's A is created at its first local alignment of a pass (b ~ N(0, c R))
         *  and marginalised out (removed from the state) once the sensor is more than
         *  view_corr_drop_lengths L from its last viewpoint, and before a wide (loop-
         *  closing) answer, which observes L with the whole R. The state carries the
         *  correlation within a pass; against earlier passes' viewpoints (fused before
         *  the current A existed) R is scaled as in `inflate` first, with the share
         *  view_corr_pass_fraction c (1: a later pass does not count their shared error
         *  again; 0: it is independent of them). */
        enum class ViewCorrModel
        {
            Inflate,
            State
        };
        ViewCorrModel view_corr_model = ViewCorrModel::Inflate;  //!< ini: view_corr_model = inflate | state
        double view_corr_drop_lengths = 3;  //!< state: A is dropped beyond this many L (rho < e^-3)
        double view_corr_pass_fraction = 1;  //!< state: earlier passes' share / c (above)
        /** > 0: a template whose d exceeds this is not aligned (`view_changed`) [m]. */
        double max_view_change_m = 0;
        /** > 0: a template whose predicted position in the sensor frame has a standard
         *  deviation (largest axis of H P H^T) above this is not aligned
         *  (`prediction_uncertain`) [m]. The matchers search locally (about 1 m): from a
         *  prediction this uncertain they lock onto whatever object lies near it, and the
         *  gate, as wide as the prediction, lets the wrong object in. */
        double max_prediction_std_m = 0;
        /** A template refused by max_prediction_std_m is searched wide instead (loop
         *  closure after drift): wideSearch over the prediction's +-3 sigma window, the
         *  answer refined by the matcher from there, the view-change guard applied to
         *  the refined pose, then the usual gate with S = H P H^T + R. */
        bool wide_search = false;
        WideSearchOptions wide{};          //!< ini: wide_* keys (README)
        double wide_max_xy_m = 40;         //!< a +-3 sigma window wider than this in x or y is refused [m]
        double wide_max_phi = 45 * M_PI / 180;  //!< or in angle [rad] (ini: wide_max_phi_deg)
        size_t wide_max_per_scan = 1;      //!< wide searches per scan (CPU bound); the rest `deferred`
        size_t wide_retry_scans = 5;       //!< a template is searched wide at most once in this many scans
        /** > 0: a wide answer is fused only when another template's wide answer within
         *  this many scans implies the same vehicle correction (a lookalike object rarely
         *  implies the same one twice); 0: fused at once. */
        size_t wide_confirm_scans = 10;
        double wide_confirm_xy_m = 1.5;    //!< corrections agree within this in x, y [m]
        double wide_confirm_phi = 4 * M_PI / 180;  //!< and this in heading [rad] (ini: wide_confirm_phi_deg)
        /** > 0: the wide search looks only at poses that place the template within this
         *  of where it was made in the sensor frame (x, y) [m], and within
         *  wide_view_window_phi of its heading then: the viewpoints from which it shows
         *  the faces it was made of (the window is the intersection with the +-3 sigma
         *  one; `view_elsewhere` when they do not meet). Elsewhere its true pose cannot
         *  match, and the best pose of a wide window is a lookalike. It also bounds the
         *  window of a very uncertain prediction. 0: the +-3 sigma window alone. */
        double wide_view_window_m = 0;
        double wide_view_window_phi = 10 * M_PI / 180;  //!< [rad] (ini: wide_view_window_phi_deg)
        double wide_cov_inflation = 1;     //!< a wide answer's R (with the viewpoint term) times this
        /** < 1: a wide answer (before its confirmation) is refused (`free_space_conflict`)
         *  when more than this share of the returns of its scan, placed by the answer,
         *  lie where the scan the template was made from saw free space, or the other way
         *  round (freeSpaceConflict, `wide_free_margin_m`, 1 deg bins): a lookalike fits
         *  the template but not the rest of the place. The landmarks keep the returns of
         *  their first scan for it. 1: off. */
        double wide_max_free_conflict = 1;
        double wide_free_margin_m = 0.5;   //!< a return conflicts when this far in front of the other scan's
        /** > 0: a template whose predicted position has a standard deviation (largest
         *  axis of H P H^T) above this is aligned with the dense map around it added
         *  (thesis 6.2: once the vehicle is no longer well correlated with the landmark,
         *  a one-scan template may lock onto a local minimum; the dense map of the
         *  object seen from everywhere it was seen is more informative). Needs an
         *  augmenter (setAugmenter; DenseSlam installs one over its regions). 0: never. */
        double augment_above_std_m = 0;
        double augment_margin_m = 2;        //!< the dense map this far around the template's bounds [m]
        size_t augment_max_points = 300;    //!< dense Gaussians added at most (evenly thinned)
        double revisit_gap_s = 30;  //!< [s] an update after this long without one is a revisit (RevisitLog)

        /** Every key, declared once (loader, unknown-key check, saver, README table). */
        core::OptionTable table();
        /** Reads [section]; unknown keys and bad values throw naming the key. */
        void load(const mrpt::config::CConfigFileBase& cfg, const std::string& section);
        void save(mrpt::config::CConfigFileBase& cfg, const std::string& section) const;
    };

    /** Counters of a run, by reason. */
    struct Stats
    {
        size_t scans = 0;
        size_t scans_empty = 0;        //!< fewer than 3 valid returns: nothing done
        size_t beams_invalid = 0;      //!< invalid, NaN/inf or out-of-range readings skipped
        size_t predicted = 0;          //!< template predictions (landmark, scan)
        size_t out_of_view = 0;        //!< in-view fraction below in_view_fraction
        size_t view_changed = 0;       //!< viewpoint moved more than max_view_change_m
        size_t prediction_uncertain = 0;  //!< predicted position std above max_prediction_std_m
        size_t aligned = 0;            //!< alignments that converged
        std::map<std::string, size_t> align_failed;  //!< by the matcher's failure reason
        size_t updated = 0;            //!< EKF updates applied
        size_t gated = 0;              //!< aligned but outside the NN gate
        size_t update_numeric = 0;     //!< innovation covariance not PD
        size_t update_invalid = 0;     //!< z or R not finite / not PD
        size_t merge_candidates = 0;   //!< pairs of templates aligned in one scan that overlap
        size_t merge_align_failed = 0; //!< of them: the two templates did not align
        size_t merge_gated = 0;        //!< of them: relative pose gated or refused by the EKF
        size_t merged = 0;             //!< of them: fused, the newer landmark removed
        size_t returns_explained = 0;  //!< returns attributed to a template
        size_t segments = 0;           //!< segments of the unexplained returns
        size_t short_runs = 0;         //!< runs of neighbours below min_points
        size_t segments_far = 0;       //!< centroid beyond max_creation_range_m
        size_t segments_collinear = 0; //!< degenerate orientation (min_spread_ratio)
        std::array<size_t, SegmentAcceptance::kOutcomes> acceptance{};  //!< by outcome
        size_t creation_failed = 0;    //!< accepted, but its own alignment gave no covariance
        size_t created = 0;            //!< new pose landmarks
        size_t augmented = 0;          //!< alignments (local or wide) of a template augmented from the dense map
        size_t augment_points = 0;     //!< dense Gaussians added over those alignments
        size_t augment_empty = 0;      //!< augmentation wanted, but the dense map held nothing around the template
        /** Wide searches by outcome: closed (fused), window_too_large, deferred,
         *  no_overlap, ambiguous, refine.<matcher reason>, view_changed, view_elsewhere,
         *  free_space_conflict, pending, confirmed, disagreed, gated, numeric. */
        std::map<std::string, size_t> wide;

        /** (name, count) of every counter, failure reasons as align_failed.<reason>. */
        std::vector<std::pair<std::string, size_t>> list() const;
    };

    /** An alignment of the last scan that converged (for scoring against a truth). */
    struct AlignedObservation
    {
        long id = 0;
        Vec3 z = Vec3::Zero();      //!< template frame in the sensor frame, aligned
        /** Its covariance as fused (inflation included; with view_corr_model = state the
         *  independent share (1 - c) R, fused into the apparent pose). */
        Mat3 R = Mat3::Zero();
        Vec3 z_hat = Vec3::Zero();  //!< the prediction the alignment started from
        bool updated = false;       //!< fused (false: gated or refused by the EKF)
        bool wide = false;          //!< found by the wide search (a re-observation after drift)
    };

    /** Reads [ScanLandmarks], [ScanSegmentation], [ScanAcceptance] and the matcher's
     *  section from `cfg` (defaults everywhere when `cfg` is null). */
    static std::unique_ptr<ScanLandmarkMap> fromConfig(const mrpt::config::CConfigFileBase* cfg);

    ScanLandmarkMap(const Options& options, const Segmenter::Options& segmentation,
                    const SegmentAcceptance::Options& acceptance,
                    std::unique_ptr<ScanMatcher> matcher);

    /** One scan: observe the templates in view, then create landmarks from what is left.
     *  The scan's sensorPose is the sensor's mounting on the vehicle. */
    void processScan(ekf::EkfSlam& ekf, const mrpt::obs::CObservation2DRangeScan& scan);

    /** Adds a pose landmark built elsewhere (e.g. a high-level landmark from the dense
     *  map, thesis 6.1): `tpl` (its frame_in_sensor is not used) becomes the template
     *  of a new EKF pose landmark initialised from the observation `obs` (template frame
     *  in the sensor frame, its covariance) by augmentation (2.3.4, Eq. 2.53); the
     *  sensor sits at `sensor` on the vehicle. From the next scan on it is observed by
     *  alignment like every other template. Throws std::invalid_argument on an empty
     *  template or an observation that is not ok. Returns the landmark id.
     *  `first_scan`: the returns (sensor frame) of the scan `obs` comes from, kept for
     *  the free-space check of its wide answers (Options::wide_max_free_conflict; none:
     *  its wide answers are not checked). */
    long addTemplateLandmark(ekf::EkfSlam& ekf, ScanTemplate tpl, const AlignResult& obs,
                             const Vec3& sensor, std::vector<Vec2> first_scan = {});

    /** The dense map's Gaussians (global frame, means and 2x2 covariances) whose means lie
     *  in the axis-aligned box [lo, hi]. */
    using Augmenter = std::function<PointSet(const Vec2& lo, const Vec2& hi)>;
    /** Source of the dense map for template augmentation (Options::augment_above_std_m);
     *  an empty function: none. Not part of the saved state: the owner installs it. */
    void setAugmenter(Augmenter f) { augmenter_ = std::move(f); }

    /** The template of landmark `id` with the augmenter's Gaussians in its bounds grown
     *  by augment_margin_m added, in the landmark frame placed at the filter's estimate
     *  of its pose; at most augment_max_points of them, evenly thinned. Returns `tpl`
     *  itself when there is no augmenter or nothing around it. */
    ScanTemplate augmentedTemplate(const ekf::EkfSlam& ekf, long id, const ScanTemplate& tpl) const;

    /** Templates by landmark id (landmarks the filter removed are dropped on the next scan). */
    const std::map<long, ScanTemplate>& templates() const { return templates_; }
    /** landmark -> the returns of its template's first scan (wide_max_free_conflict < 1). */
    const std::map<long, std::vector<Vec2>>& firstScans() const { return first_scans_; }
    const Stats& stats() const { return stats_; }
    const std::vector<RevisitLog::Revisit>& revisits() const { return revisits_.list(); }  //!< in order
    /** The converged alignments of the last processScan call. */
    const std::vector<AlignedObservation>& lastAligned() const { return last_aligned_; }
    const Options& options() const { return options_; }
    const ScanMatcher& matcher() const { return *matcher_; }

    /** Templates, counters, the acceptance test's generator and the last scan's
     *  alignments bit for bit, for a saved run (hymm-slam --save-state / --resume); the
     *  options are the config's, not saved. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

private:
    /** Observes landmark `id` in `pts`; marks the returns it explains. */
    void observe(ekf::EkfSlam& ekf, long id, const ScanTemplate& tpl, const PointSet& pts,
                 const Vec3& sensor, double max_range, double fov, std::vector<char>& explained);
    /** Aligns `aligned` (the template `tpl`, augmented or not) from z_hat and fuses the
     *  result through the NN gate; returns where its returns are (z_hat unless fused). */
    Vec3 alignAndUpdate(ekf::EkfSlam& ekf, long id, const ScanTemplate& tpl, const PointSet& aligned,
                        const PointSet& pts, const Vec3& sensor, double max_range, double fov,
                        const Vec3& z_hat);
    /** H P H^T of landmark `id` seen from `sensor`: the predicted template pose's
     *  covariance in the sensor frame. */
    Mat3 predictionCov(const ekf::EkfSlam& ekf, long id, const Vec3& sensor) const;
    /** The wide search of a template whose prediction `S` is too uncertain; returns
     *  where its returns are (z_hat unless fused). ScanLandmarkWide.cpp. */
    Vec3 observeWide(ekf::EkfSlam& ekf, long id, const ScanTemplate& tpl, const PointSet& pts,
                     const Vec3& sensor, const Vec3& z_hat, const Mat3& S);
    /** Whether the scan `pts`, placed by the wide answer z of landmark `id`, and the
     *  template's first scan contradict each other beyond wide_max_free_conflict
     *  (counted as free_space_conflict; false when the first scan is not kept). */
    bool refusedByFirstScan(long id, const ScanTemplate& tpl, const PointSet& pts, const Vec3& z);
    /** Whether the wide answer z of landmark `id` agrees with the pending one of another
     *  landmark (same implied vehicle correction); else it becomes the pending one. */
    bool confirmWide(const ekf::EkfSlam& ekf, long id, const Vec3& z, const Vec3& sensor);
    /** The matcher's covariance `R` plus the viewpoint term of Options (view_std_*) for a
     *  viewpoint change of `d` metres (viewChange). */
    Mat3 viewCovariance(const Mat3& R, double d) const;
    /** The factor on R of an alignment of landmark `id` from the viewpoint `view`
     *  (sensor position in the template frame) with the correlated share `c`, against
     *  its first `n_views` fused viewpoints; 1 when c is 0 or the template was never
     *  fused. */
    double viewCorrelationFactor(long id, const Vec2& view, double c,
                                 size_t n_views = std::numeric_limits<size_t>::max()) const;
    /** view_corr_model = state: relaxes (or creates) the apparent-pose block of landmark
     *  `id` for an alignment from `view` with covariance `R` (sensor frame, whole);
     *  returns the block to update. */
    long apparentBlock(ekf::EkfSlam& ekf, long id, const Vec2& view, const Mat3& R, const Vec3& sensor);
    size_t fusedViews(long id) const;  //!< number of fused viewpoints of landmark `id`
    /** view_corr_model = state: marginalises out the apparent-pose blocks of removed
     *  templates and of those whose last viewpoint is far from the sensor now. */
    void dropApparentBlocks(ekf::EkfSlam& ekf, const Vec3& sensor);
    struct Apparent;
    /** Marginalises out the apparent-pose block at `it` (none at end()); returns the next. */
    std::map<long, Apparent>::iterator dropApparentBlock(ekf::EkfSlam& ekf, std::map<long, Apparent>::iterator it);
    /** merge_duplicates: the landmarks of last_aligned_ and the ones they overlap become
     *  one (ScanLandmarkMerge.cpp). */
    void mergeDuplicates(ekf::EkfSlam& ekf);
    /** Aligns the two templates, fuses the relative pose, removes `drop`; false if not. */
    bool mergePair(ekf::EkfSlam& ekf, long keep, long drop);
    /** Segments the unexplained returns and adds the accepted ones as landmarks. */
    void createLandmarks(ekf::EkfSlam& ekf, const PointSet& pts, const Vec3& sensor,
                         const std::vector<char>& explained);

    Options options_;
    Augmenter augmenter_;
    Segmenter segmenter_;
    std::unique_ptr<ScanMatcher> matcher_;
    SegmentAcceptance acceptance_;
    std::map<long, ScanTemplate> templates_;
    Stats stats_;
    std::vector<AlignedObservation> last_aligned_;
    size_t wide_this_scan_ = 0;
    std::map<long, size_t> wide_last_;  //!< landmark -> scan of its last wide search
    /** landmark -> viewpoints (sensor position in the template frame) of its fused
     *  alignments (Options::view_corr_share). */
    std::map<long, std::vector<Vec2>> fused_views_;
    /** view_corr_model = state: landmark -> its apparent-pose block and the viewpoint of
     *  that block's last step. */
    struct Apparent
    {
        long block = -1;
        Vec2 view = Vec2::Zero();
        size_t first_view = 0;  //!< fused_views_ of the landmark before this block existed
    };
    std::map<long, Apparent> apparent_;
    /** (kept, dropped) -> scan of the last failed merge attempt (merge_retry_scans). */
    std::map<std::pair<long, long>, size_t> merge_last_;
    /** The last unconfirmed wide answer: its landmark, scan and implied vehicle correction. */
    struct WidePending
    {
        long id = -1;
        size_t scan = 0;
        Vec3 correction = Vec3::Zero();
    };
    /** landmark -> the returns of the scan its template was made from (sensor frame),
     *  with wide_max_free_conflict < 1. */
    std::map<long, std::vector<Vec2>> first_scans_;
    RevisitLog revisits_;
    void countUpdate(long id, bool wide);  //!< an EKF update of landmark `id` applied: counted, revisit noted
    bool keepsFirstScans() const { return options_.wide_search && options_.wide_max_free_conflict < 1; }
    WidePending wide_pending_;
};

/** Whether the points of `set` span two dimensions: the smaller standard deviation of
 *  their scatter is at least `min_ratio` times the larger (false for < 3 points). */
bool hasOrientation(const PointSet& set, double min_ratio);

}  // namespace hymm::scanslam
