/**
 * @file outside_causes.h
 * @brief Why a laser return fell in no Local Triangular Region: a diagnostic that asks,
 *        for the return's position, what the partition and the landmark map allow there
 *        (evaluated on the map as it is when called, e.g. at the end of a run).
 *
 * Causes, in the order they are tested:
 *  - InRegionNow: a region of the partition holds the point now: it formed after the
 *    return was seen (what the delayed store, Sec. 3.7.3, is for);
 *  - NoLandmarkTriangle: no triangle of real landmarks near the point contains it (the
 *    point lies beyond the landmarks, e.g. objects behind the outer row of trees): only a
 *    virtual landmark (Sec. 3.5.1) or a fallback can hold it;
 *  - otherwise the triangle a Delaunay partition would use there (of the triangles of the
 *    `nearest` nearest real landmarks containing the point and holding no other of them,
 *    the one with the shortest longest edge) is checked against the Sec. 3.5 conditions,
 *    the overlap with the existing regions included, and its first failing condition is
 *    the cause: LongEdge (max_edge_length_m), Shape (area, angle, condition number,
 *    ellipses reaching an edge: condition 2), Correlation (condition 1, vertex pairs or
 *    vehicle), Overlap (the triangle crosses existing regions, so the growth can never
 *    place it);
 *  - NotGrown: that triangle passes every condition; the growth, which proposes
 *    triangles only around the vehicle (search_radius_m) and from the free edges of
 *    existing regions, never reached it.
 */
#pragma once

#include "hymm/ltr/LandmarkCovarianceView.h"
#include "hymm/ltr/RegionPartition.h"

#include <array>
#include <string>

namespace hymm::ltr
{
enum class OutsideCause
{
    InRegionNow = 0,
    NoLandmarkTriangle,
    LongEdge,
    Shape,
    Correlation,
    Overlap,
    NotGrown,
    Count
};

/** Stable snake_case name, e.g. "no_landmark_triangle". */
const char* toString(OutsideCause c);

/** Classifies one return position (see the file comment). `nearest` (>= 3): real
 *  landmarks considered, nearest first, within the partition's max_edge_length_m. */
OutsideCause classifyOutsideReturn(
    const RegionPartition& partition, const LandmarkCovarianceView& view, const Eigen::Vector2d& p,
    int nearest = 8);

/** Counts per cause. */
struct OutsideCauseCounts
{
    std::array<size_t, static_cast<size_t>(OutsideCause::Count)> n{};
    size_t total() const;
    size_t& operator[](OutsideCause c) { return n[static_cast<size_t>(c)]; }
    size_t operator[](OutsideCause c) const { return n[static_cast<size_t>(c)]; }
};

}  // namespace hymm::ltr
