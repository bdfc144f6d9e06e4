/**
 * @file PotentialRegionSet.h
 * @brief Potential Local Triangular Regions (thesis Sec. 3.7.3): triangles of feature-map
 *        landmarks that meet the geometry and no-overlap conditions of Sec. 3.5 but not
 *        (yet) the correlation condition. Delayed returns are stored relative to one.
 *
 * A potential region is a triple of confirmed 2D point landmarks of the EKF that
 *  - passes BaseConditionChecker::checkGeometry (area, angles, edge length, condition
 *    number, n-sigma ellipse / flip test) on the current estimates,
 *  - does not overlap the current triangle of any real region of the partition, nor any
 *    other potential region of this set,
 *  - holds no other candidate landmark strictly inside (the partition grows Delaunay-like
 *    triangles, so such a triangle would never become a region).
 * The correlation condition is deliberately not checked: that is what the store waits for.
 *
 * Costs: refresh() is O(number of potential regions) plus one grid lookup each;
 * assign() is O(points x potential regions) and, only when some point is not covered,
 * O(n) over the landmark ids plus O(k^3 x points) over the k nearest candidates.
 */
#pragma once

#include <hymm/ekf/EkfSlam.h>
#include <hymm/ltr/RegionPartition.h>
#include <hymm/ltr/TriangleFrame.h>

#include <Eigen/Core>

#include <array>
#include <map>
#include <vector>

namespace mrpt::serialization
{
class CArchive;
}

namespace hymm::uif
{
struct PotentialRegion
{
    long id = -1;
    std::array<long, 3> vertex_ids{{-1, -1, -1}};  //!< EKF landmark ids of L1, L2, L3
};

class PotentialRegionSet
{
public:
    /** `search_radius_m`: candidate vertices lie this close to the vehicle;
     *  `max_candidate_landmarks` (>= 3): the nearest ones tried. */
    PotentialRegionSet(double search_radius_m, int max_candidate_landmarks);

    /** Drops potential regions that lost a vertex, fail the geometry condition or now
     *  overlap a real region. Returns how many were dropped. */
    size_t refresh(const hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition);

    /**
     * For each global point, the id of a potential region whose current triangle contains
     * it, or -1. Existing potential regions are tried first; for points still uncovered,
     * new ones are built greedily among the landmarks nearest to `centre` (the triangle
     * covering the most uncovered points first). Call refresh() first.
     */
    std::vector<long> assign(
        const std::vector<Eigen::Vector2d>& points, const hymm::ekf::EkfSlam& ekf,
        const hymm::ltr::RegionPartition& partition, const Eigen::Vector2d& centre);

    /** Removes potential regions no stored point refers to (ids not in `in_use`). */
    void retainOnly(std::vector<long> in_use);

    size_t size() const { return regions_.size(); }
    /** Saved run state (hymm-slam --save-state): every member a later step reads, bit
     *  for bit; loadState() replaces them (options come from the config). Throws
     *  std::runtime_error on a corrupt or truncated state. Source: DelayedDenseStoreState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);
    bool has(long id) const { return regions_.count(id) != 0; }
    /** Throws std::out_of_range for an unknown id. */
    const PotentialRegion& region(long id) const;
    std::vector<long> ids() const;
    void clear() { regions_.clear(); }

    /** Current vertex means of `ids` in the EKF; false if one is missing or not a 2D point. */
    static bool currentVertices(
        const hymm::ekf::EkfSlam& ekf, const std::array<long, 3>& ids,
        hymm::ltr::TriangleFrame::Vertices& v);

private:
    struct Candidate
    {
        std::array<long, 3> ids;
        hymm::ltr::TriangleFrame::Vertices v;
    };
    bool passesGeometryAndOverlap(
        const hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition,
        const std::array<long, 3>& ids, const hymm::ltr::TriangleFrame::Vertices& v) const;
    std::vector<Candidate> candidates(
        const hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition,
        const Eigen::Vector2d& centre) const;

    const double search_radius_m_;
    const int max_candidate_landmarks_;
    std::map<long, PotentialRegion> regions_;
    long next_id_ = 0;
};

}  // namespace hymm::uif
