/**
 * @file WideSearch.h
 * @brief Wide (global within a window) alignment of a template for a re-observation
 *        whose prediction is too uncertain for the local matchers' basin (about 1 m):
 *        a coarse-to-fine correlative search (Olson 2009's multi-resolution idea) over
 *        the prediction's +-3 sigma window in x, y and phi. Level A scores every pose of
 *        the window on a likelihood grid smoothed to its step; the best separate level-A
 *        cells are refined at level B; the answer is accepted only when it is
 *        distinctive: the best refined peak's goodness (mean point likelihood) clearly
 *        above the best SEPARATE peak's (ambiguity ratio) and enough template points
 *        matched (overlap). The caller refines the answer with its normal matcher and
 *        gates it with S = H P H^T + R (ScanLandmarkMap).
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <mrpt/config/CConfigFileBase.h>

#include <string>

#include "hymm/scanslam/PointSet.h"

namespace hymm::scanslam
{
struct WideSearchOptions
{
    double coarse_step_m = 1.0;       //!< level-A translation step (and likelihood std) [m]
    double fine_step_m = 0.2;         //!< level-B translation step [m]
    double fine_sigma_m = 0.15;       //!< level-B point likelihood std [m]
    double gate_sigma = 3.0;          //!< log-likelihood floor at this distance [sigma]
    double max_gap_m = 0.5;           //!< level B: consecutive returns closer are joined by a surface
    int candidates = 12;              //!< separate level-A cells refined at level B
    size_t max_points = 48;           //!< level A scores an even subsample of this many points
    double peak_separation_m = 1.0;   //!< peaks closer (any template point moved less) are one
    double max_ambiguity = 0.85;      //!< second separate peak's goodness / best's must be below
    double min_matched_fraction = 0.7;  //!< template points within the gate at the best pose
};

struct WideResult
{
    bool ok = false;
    Vec3 z = Vec3::Zero();      //!< best level-B pose (template frame in the scan frame)
    double goodness = 0;        //!< mean point likelihood exp(loglik) at z, in [0, 1]
    double second = 0;          //!< the same for the best separate peak (0: none)
    double matched_fraction = 0;  //!< template points within the gate at z
    size_t poses = 0;           //!< poses scored (levels A and B)
    const char* failure = "";   //!< no_overlap | ambiguous | empty
};

/** Searches the template pose in the window z0 +- half (x, y [m], phi [rad]); the
 *  caller caps the window. Never throws on data. */
WideResult wideSearch(const PointSet& tpl, const PointSet& scan, const Vec3& z0, const Vec3& half,
                      const WideSearchOptions& o);

/** How much two scans contradict each other at a relative pose (the verification of a
 *  wide answer against the whole scan its template was made from). A return of one scan
 *  conflicts when it lies in the space the other saw free: in front, by more than
 *  `margin_m`, of the other's nearest return on its bearing and on both neighbouring
 *  bearing bins (`bin_rad` wide). A return on a bearing where the other scan has no
 *  return nearby is not tested: no return is no evidence. Each direction is counted on
 *  its own; a lookalike place that fits a template puts walls where the other scan
 *  looked through, a true revisit only where something moved or a beam grazed. */
struct FreeSpaceConflict
{
    size_t tested_ab = 0;     //!< returns of b tested against a's free space
    size_t conflicts_ab = 0;  //!< of those, in it
    size_t tested_ba = 0;     //!< returns of a tested against b's free space
    size_t conflicts_ba = 0;
    /** The larger share of conflicts over the directions with at least `min_tested`
     *  returns tested (0 when neither has). */
    double share(size_t min_tested) const;
};

/** `a`, `b`: returns in their own sensor frames; `b_in_a`: b's sensor pose in a's. */
FreeSpaceConflict freeSpaceConflict(const std::vector<Vec2>& a, const std::vector<Vec2>& b, const Vec3& b_in_a,
                                    double margin_m, double bin_rad);

}  // namespace hymm::scanslam
