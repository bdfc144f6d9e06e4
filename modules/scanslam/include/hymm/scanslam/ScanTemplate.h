/**
 * @file ScanTemplate.h
 * @brief A scan landmark's template (thesis 5.2.1, 5.2.3): the accepted points as a
 *        sum of Gaussians in a frame local to the landmark, origin at their centroid,
 *        orientation that of the sensor at creation. The template stays outside the
 *        EKF state; only the frame's pose enters it.
 */
#pragma once

#include "hymm/scanslam/PointSet.h"
#include "hymm/scanslam/Segmenter.h"

#include <mrpt/serialization/CArchive.h>

namespace hymm::scanslam
{
struct ScanTemplate
{
    PointSet sog;  //!< points and covariances in the landmark frame
    /** Pose of the landmark frame in the sensor frame it was made from (centroid, 0). */
    Vec3 frame_in_sensor = Vec3::Zero();

    /** Template of the points `segment` of `scan` (sensor frame). */
    static ScanTemplate fromSegment(const PointSet& scan, const Segmenter::Segment& segment);
    /** Template of all points of `points` (sensor frame). */
    static ScanTemplate fromPoints(const PointSet& points);

    /** Bit for bit, for a saved run (core/state_archive.h). */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);
};

/** A point set bit for bit, for a saved run. */
void savePointSet(mrpt::serialization::CArchive& out, const PointSet& p);
void loadPointSet(mrpt::serialization::CArchive& in, PointSet& p);

/** Largest distance of a template point from its frame's origin. */
double templateRadius(const ScanTemplate& tpl);

/** How far the template frame at `z` (sensor frame) is from where it was made in the
 *  sensor frame: the viewpoint change d of the alignment covariance's viewpoint term. */
inline double viewChange(const ScanTemplate& tpl, const Vec3& z)
{
    return (z.head<2>() - tpl.frame_in_sensor.head<2>()).norm();
}

/** Fraction of the template's points that fall inside the sensor's view (range below
 *  `max_range_m`, |bearing| <= fov/2) when the template frame sits at `z` in the sensor
 *  frame. Thesis 5.7: a landmark is in view when this exceeds 0.9. */
double fractionInView(const ScanTemplate& tpl, const Vec3& z, double max_range_m, double fov);

/** The points of `tpl` (landmark frame) a sensor would see when the template frame sits
 *  at `z` in the sensor frame: in range and field of view, and not hidden behind another
 *  template point of the same bearing (a z-buffer over bearing bins of `bin_rad`; a
 *  point within `depth_tol_m` of the nearest one of its bin is seen). A template made
 *  from many vantage points (e.g. a high-level landmark from the dense map, thesis 6.1)
 *  holds sides a single scan cannot see; aligning those would pull the template to
 *  match the scan with them. */
PointSet visiblePart(const PointSet& tpl, const Vec3& z, double max_range_m, double fov,
                     double bin_rad, double depth_tol_m);

}  // namespace hymm::scanslam
