/**
 * @file motion_outputs.h
 * @brief Scores and figures of the motion layers (thesis Sec. 6.3.3, Fig. 6.9-6.10)
 *        of a DenseSlam run against the simulator's truth.
 *
 * Truth (MotionTruth): footprints of every object that is not static (moved, added or
 * removed), grouped per object, and the outlines of the static objects. From the
 * simulator's World (tests) or from its `_gt_objects.txt` records (hymm-slam).
 *
 * Scoring (scoreMotionLayer), on a global grid at the current landmark estimates, only
 * over the cells a region or fallback tile with an occupancy layer covers (no layer can
 * mark elsewhere):
 *  - precision: marked cells within `tolerance` cells of a non-static footprint;
 *  - recall: footprint cells within `tolerance` of a marked cell. A footprint's far side
 *    is never seen by the sensor, so this recall is bounded below 1 by visibility;
 *    scoreAgainst() takes any other truth (e.g. the surface the beams met);
 *  - static_fp_fraction: static-outline cells (band of half a cell either side)
 *    marked, over all static-outline cells;
 *  - per object: recall and whether any marked cell lies within tolerance ("detected").
 */
#pragma once

#include <hymm/dense/outline_metrics.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/dynamic/MotionDetector.h>
#include <hymm/eval/MetricsJson.h>
#include <hymm/eval/motion_metrics.h>
#include <hymm/sim/World.h>
#include <hymm/sim/ground_truth_io.h>

#include <map>
#include <string>
#include <vector>

namespace hymm::app
{
using denseslam::DenseSlam;

struct MotionTruth
{
    /** Per non-static object (name or "object_<id>"): every footprint it took. */
    std::map<std::string, std::vector<dense::Polygon>> moving;
    std::vector<dense::Polygon> static_outlines;
};

/** From the world: footprints sampled every `dt` over [t0, t1], plus the footprints of
 *  objects present only part of that time; the static outlines include the landmark
 *  trunks. */
MotionTruth motionTruthFromWorld(const sim::World& world, double t0, double t1, double dt);
/** From `_gt_objects.txt` records: an object with one record spanning [t_first, t_last]
 *  of the file is static, any other is moving (every record a footprint). */
MotionTruth motionTruthFromRecords(const std::vector<sim::ObjectOutlineRecord>& records);

struct MotionScore
{
    eval::DetectionScore total;
    std::map<std::string, eval::DetectionScore> per_object;
    size_t static_cells = 0;      //!< static-outline cells in the covered area
    size_t static_marked = 0;     //!< of those, marked
    double static_fp_fraction = 0;
    size_t covered_cells = 0;     //!< grid cells inside a region with occupancy
};

/** Grid at `resolution` over the regions with occupancy (the same box renderOccupancy
 *  uses), its covered cells, and the motion layer of `kind` drawn on it. */
struct MotionRaster
{
    eval::CellMask covered, marked;
};
MotionRaster rasterMotionLayer(const DenseSlam& slam, dynamic::MotionKind kind, double resolution);

/** The scores above; throws std::logic_error without a motion hook. */
MotionScore scoreMotionLayer(const DenseSlam& slam, dynamic::MotionKind kind, const MotionTruth& truth,
                             double resolution, int tolerance);
/** Precision / recall of the layer against an arbitrary truth mask built on `raster`'s
 *  grid (restricted to the covered cells). */
eval::DetectionScore scoreAgainst(const MotionRaster& raster, const eval::CellMask& truth, int tolerance);

/** "dynamic.<kind>.*" keys: precision, recall, static_fp_fraction, cells, and per
 *  object "dynamic.<kind>.object.<name>.recall|detected"; plus "dynamic.*" counters of
 *  the hook. Cell size: the occupancy layer's. */
void writeMotionMetrics(eval::MetricsJson& j, const DenseSlam& slam, const MotionTruth& truth);

/** Figures as Fig. 6.9 / 6.10 into `dir`: motion_<kind>.png (the layer over the
 *  occupancy, marked cells black), motion_<kind>_raw.png / _filtered.png (the last
 *  differencing that marked anything: |dP| and after the low-pass, in its region's
 *  reference frame), occupancy_static.png (dynamic cells at the prior). */
void writeMotionOutputs(const DenseSlam& slam, const std::string& dir, bool png = true);

}  // namespace hymm::app
