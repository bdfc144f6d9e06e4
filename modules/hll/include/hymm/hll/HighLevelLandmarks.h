/**
 * @file HighLevelLandmarks.h
 * @brief High-level landmarks in the feature map (thesis 6.1): the detector of
 *        HllDetector.h run every `period_s` of log time near the vehicle; each accepted
 *        rectangle becomes a template of the SOG Gaussians inside it, in the
 *        rectangle's frame (Scan-SLAM representation, 5.2.3; state Eq. 6.1-6.4).
 *
 * Life of an HLL:
 *  1. pending ("passive" in the thesis): the template and the pose of its frame in the
 *     map at detection; nothing enters the filter, the map estimate is used only to
 *     predict where the vehicle will see it;
 *  2. initialised at its next observation (thesis 6.1.1, 2.3.4): when more than
 *     `in_view_fraction` of its points are in the sensor's view at the predicted pose,
 *     the template is aligned to the scan (the Scan-SLAM matcher) and the pose landmark
 *     is added from that observation alone by augmentation (ScanLandmarkMap::
 *     addTemplateLandmark), so the dense map's estimate of the area (made from the same
 *     vehicle poses) is not used twice;
 *  3. observed by scan alignment on every scan from then on (ScanLandmarkMap with
 *     create_landmarks = false: the same in-view test, alignment, NN gate and pose
 *     update as every scan landmark).
 * A candidate overlapping the area of an HLL (pending or in the filter) or of an area
 * the caller passes (e.g. Scan-SLAM templates) is rejected: no duplicates.
 *
 * Ini: [HighLevelLandmarks] (keys of HllDetector::Options and the ones below) and the
 * matcher's section [HllMatcher] (keys of [SogMatcher] / [IcpMatcher] /
 * [CorrelativeMatcher] for the chosen matcher). Key table in the module README.
 */
#pragma once

#include <hymm/ekf/EkfSlam.h>
#include <hymm/scanslam/ScanLandmarkMap.h>
#include <mrpt/config/CConfigFileBase.h>

#include <limits>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "hymm/hll/HllDetector.h"

namespace hymm::hll
{
class HighLevelLandmarks
{
public:
    struct Options
    {
        bool enabled = false;          //!< ini: the pipeline builds HLLs only when true
        HllDetector::Options detector;
        std::string matcher = "sog";   //!< sog | icp | correlative (section [HllMatcher])
        double in_view_fraction = 0.9; //!< thesis 5.7 in-view test, for initialisation and updates
        double gate_prob = 0.99;       //!< NN gate on an aligned observation
        size_t template_max_points = 400;  //!< templates are thinned to at most this many Gaussians
        double std_range_m = 0.1;      //!< laser noise of the scan points the templates are aligned to
        double std_bearing = M_PI / 180;  //!< [rad] (ini: std_bearing_deg)
        /** Alignments use only the template points visible from the prediction
         *  (scanslam::visiblePart, bearing bins of this size): an HLL template holds
         *  every side of its objects, a scan only the near ones. (ini: visible_bin_deg) */
        double visible_bin = M_PI / 180;
        double visible_depth_tol_m = 0.3;  //!< visiblePart's depth tolerance [m]
        double explain_distance_m = 1.0;  //!< as [ScanLandmarks]

        /** Every key of [HighLevelLandmarks], declared once. */
        core::OptionTable table();
    };

    /** One high-level landmark. */
    struct Hll
    {
        size_t index = 0;               //!< order of acceptance
        OrientedRect rect;              //!< at detection, global frame (its frame = the HLL's)
        scanslam::ScanTemplate tpl;     //!< Gaussians in the rectangle's frame
        size_t gaussians = 0;           //!< inside the rectangle at detection (before thinning)
        double outline_m = 0;           //!< [m] outline length inside it at detection (outlineInside)
        double t_accepted = 0;
        long landmark_id = -1;          //!< EKF pose landmark once initialised
        double t_initialised = -1;
    };

    struct Stats
    {
        size_t searches = 0;
        size_t regions_searched = 0;    //!< summed over searches
        size_t components_dropped = 0;  //!< occupied components too small for an object (poles)
        size_t corners_near_landmark = 0;  //!< corners dropped on a point landmark
        size_t corners = 0;             //!< summed over searches (kept ones)
        size_t proposed = 0;            //!< candidate rectangles (pairs)
        size_t accepted = 0;
        size_t rejected_few_gaussians = 0;
        size_t rejected_short_outline = 0;
        size_t rejected_overlap_landmark = 0;
        size_t rejected_overlap_candidate = 0;
        size_t init_attempts = 0;       //!< pending HLLs in view
        size_t init_align_failed = 0;   //!< of those, alignment failed
        size_t initialised = 0;
        size_t lost = 0;                //!< initialised, then removed from the filter
        std::vector<std::pair<std::string, size_t>> list() const;
    };

    /** Reads [HighLevelLandmarks] and [HllMatcher] (defaults when `cfg` is null). */
    static Options loadOptions(const mrpt::config::CConfigFileBase* cfg);
    HighLevelLandmarks(const Options& options, std::unique_ptr<scanslam::ScanMatcher> matcher);
    static std::unique_ptr<HighLevelLandmarks> fromConfig(const mrpt::config::CConfigFileBase* cfg);
    /** With `options` (e.g. loadOptions' result) and the matcher of options.matcher read
     *  from [HllMatcher] of `cfg` (defaults when null). */
    static std::unique_ptr<HighLevelLandmarks> make(const Options& options,
                                                    const mrpt::config::CConfigFileBase* cfg);

    /** Whether a search is due at log time `t` (the first call starts the clock). */
    bool due(double t);
    /** One search around the vehicle of `ekf`; accepted rectangles become pending HLLs.
     *  `exclusions`: areas of other landmarks (global) candidates must not meet. */
    const HllDetector::Search& search(double t, const ekf::EkfSlam& ekf,
                                      const ltr::RegionPartition& partition,
                                      const dense::HybridMetricMap& map,
                                      const std::vector<OrientedRect>& exclusions = {});
    /** Adds a pending HLL: `tpl` in the frame of `rect` (global at detection). search()
     *  adds the accepted rectangles this way. Returns its index. */
    size_t addPending(const OrientedRect& rect, scanslam::ScanTemplate tpl, size_t gaussians, double t,
                      double outline_m = 0);
    /** One scan: pending HLLs in view are initialised, those in the filter observed. */
    void processScan(ekf::EkfSlam& ekf, const mrpt::obs::CObservation2DRangeScan& scan, double t);

    /** The area of every HLL now: in the filter at its estimate, pending at detection. */
    std::vector<OrientedRect> areas(const ekf::EkfSlam& ekf) const;

    const std::vector<Hll>& hlls() const { return hlls_; }
    /** Every search made, in order (for the figure of Fig. 6.5; Gaussians dropped). */
    const std::vector<HllDetector::Search>& searches() const { return searches_; }
    const Stats& stats() const { return stats_; }
    /** The observation step of the HLLs in the filter (its stats: updated, gated, ...). */
    const scanslam::ScanLandmarkMap& tracker() const { return *tracker_; }
    const Options& options() const { return options_; }
    /** EKF updates and augmentations made so far. */
    size_t mapChanges() const { return tracker_->stats().updated + tracker_->stats().created; }

    /** The HLLs (pending and initialised, with their templates), the searches behind the
     *  figures, the counters, the last search time and the tracker's state bit for bit,
     *  for a saved run (hymm-slam --save-state / --resume). */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

    /** The template of the Gaussians of `gaussians` inside `rect`, in its frame,
     *  thinned to `max_points` by an even stride. */
    static scanslam::ScanTemplate makeTemplate(const OrientedRect& rect,
                                               const std::vector<HllDetector::Gaussian>& gaussians,
                                               size_t max_points);

private:
    Options options_;
    HllDetector detector_;
    std::unique_ptr<scanslam::ScanLandmarkMap> tracker_;
    std::vector<Hll> hlls_;
    std::vector<HllDetector::Search> searches_;
    Stats stats_;
    double last_search_t_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace hymm::hll
