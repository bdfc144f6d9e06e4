/**
 * @file matcher_pairs.h
 * @brief Pairs of simulated scans of known polygons for the matcher tests: a template
 *        from one scan, the other scan, and the true pose of the template frame in it.
 */
#pragma once

#include <hymm/scanslam/ScanMatcher.h>
#include <hymm/scanslam/Segmenter.h>

#include <utility>
#include <vector>

#include "sim_scenes.h"

namespace hymm::scanslam::testing
{
/** A template from the scan at pose A and the scan at pose B of the same world, with
 *  the true pose of the template frame in B's sensor frame. */
struct Pair
{
    ScanTemplate tpl;
    PointSet scan;
    Vec3 truth;
};

inline bool makePair(const hymm::sim::World& world, const Vec3& a, const Vec3& b, uint32_t seed,
              size_t which, Pair& out)
{
    // Thesis Table 5.1 laser (the regime the default cov_inflation was measured in, on
    // other worlds: benchmarks/scan_matchers).
    const Laser laser{0.1, 1.0, 30, 0.5};
    const PointSet sa = simulate(world, a, seed, laser);
    Segmenter::Options so;
    so.min_points = 15;
    so.max_range_gap_m = 1.0;
    const auto segs = Segmenter(so).segment(sa);
    if (segs.size() <= which) return false;
    out.tpl = ScanTemplate::fromSegment(sa, segs[which]);
    out.scan = simulate(world, b, seed + 500, laser);
    out.truth = compose(inverse(b), compose(a, out.tpl.frame_in_sensor));
    return true;
}

/** An L-shaped object (box seen corner-on) and a second box: well-conditioned. */
inline hymm::sim::World lWorld()
{
    std::vector<hymm::sim::WorldObject> objs;
    objs.push_back(fixedObject(0, box(4, 3), 8, 2, 1.03));
    objs.push_back(fixedObject(1, box(3, 2), 7, -5, -0.4));
    return hymm::sim::World({}, std::move(objs));
}

}  // namespace hymm::scanslam::testing
