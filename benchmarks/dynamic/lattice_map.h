// The lattice map of the motion-layer benchmarks (thesis Sec. 6.3): N regions on a
// square lattice of landmarks (5 m spacing), the map growing outwards from its centre,
// every region's occupancy filled (0.2 m cells), and the "vehicle" on a circle around
// the centre. The regions in view are fixed by distance from the vehicle, so their
// number is the same at every map size that covers the circle and the view.
#pragma once

#include "synthetic_partition.h"

#include <hymm/dense/HybridMetricMap.h>

#include <cmath>
#include <vector>

namespace hymm::dynamic::bench
{
using namespace hymm::dense::synthetic;
using V2 = Eigen::Vector2d;
constexpr double kSpacing = 5.0;

/** Returns at `range` over the half circle ahead of the sensor, 1 degree apart; the
 *  bearings in [gap_from, gap_to] (rad) return at `gap_range` instead (an object's near
 *  face). */
inline hymm::dense::ScanPoints ringScan(double range = 6.0, double gap_from = 0, double gap_to = -1,
                                        double gap_range = 0)
{
    hymm::dense::ScanPoints s;
    for (int k = 0; k < 181; ++k)
    {
        const double a = -M_PI / 2 + M_PI * k / 180.0;
        const double r = a >= gap_from && a <= gap_to ? gap_range : range;
        s.points.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    return s;
}

struct LatticeMap
{
    int side;
    Lattice lattice;
    IndependentLandmarksView view;
    hymm::ltr::RegionPartition partition{permissivePartitionOptions()};
    V2 centre;
    hymm::dense::HybridMetricMap map;

    static hymm::dense::HybridMetricMap::Options mapOptions(bool fallback = false)
    {
        hymm::dense::HybridMetricMap::Options mo;
        mo.enable_points = false;
        mo.occupancy.cell_size_m = 0.2;
        if (fallback) mo.fallback_max_distance_m = 10.0;  // tiles of 10 m (the default)
        return mo;
    }
    /** `side` is even for every N used (100, 500, 2000, 8000): the centre then falls on
     *  the same point of a lattice square and the geometry around it is the same.
     *  `fallback`: the map keeps fallback tiles too, and every lattice square puts one
     *  return into a tile of the region holding it (about one tile per region, the
     *  density of a long run's boundary everywhere). */
    explicit LatticeMap(size_t regions, bool fallback = false)
        : side(static_cast<int>(std::ceil(std::sqrt(static_cast<double>(regions) / 2.0))) + 2),
          lattice{side, side, kSpacing, V2(0, 0)},
          view(lattice.landmarks()),
          centre(0.5 * kSpacing * (side - 1) * V2(1, 1)),
          map(mapOptions(fallback))
    {
        addRegions(partition, view, lattice.triangles(centre), regions);
        const auto scan = ringScan();
        for (int i = 0; i < side; ++i)
            for (int j = 0; j < side; ++j)
                map.insertScan(scan, {kSpacing * (i + 0.5), kSpacing * (j + 0.5), 0.0}, partition);
        if (!fallback) return;
        for (int i = 0; i < side; ++i)
            for (int j = 0; j < side; ++j)
            {
                const V2 p(kSpacing * (i + 0.3), kSpacing * (j + 0.6));
                map.insertFallbackReturn(p - V2(1.0, 0.0), p, 0.05, 0.01, partition);
            }
    }
    /** Vehicle position at time t: a circle of radius 4 m around the centre, one lap
     *  in ~126 s. */
    V2 vehicle(double t) const
    {
        const double a = 0.05 * t;
        return centre + 4.0 * V2(std::cos(a), std::sin(a));
    }
    /** Regions whose current triangle's centroid lies within `radius` of the vehicle at
     *  t, sorted by id: with the 4 m circle and 14 m, about 50 regions, all within 18 m
     *  of the centre, which the 100-region map (~20 m) covers. */
    std::vector<long> inView(double t, double radius = 14.0) const
    {
        const V2 v = vehicle(t);
        std::vector<long> out;
        for (long id : partition.regionsInBox(v - V2(radius, radius), v + V2(radius, radius)))
        {
            const auto& c = partition.region(id).current;
            if (((c[0] + c[1] + c[2]) / 3.0 - v).norm() <= radius) out.push_back(id);
        }
        return out;
    }
    /** inView at t0, t0 + dt, ... for `calls` calls: computed before the timed calls. */
    std::vector<std::vector<long>> viewSchedule(double t0, double dt, size_t calls,
                                                double radius = 14.0) const
    {
        std::vector<std::vector<long>> out(calls);
        for (size_t k = 0; k < calls; ++k) out[k] = inView(t0 + dt * static_cast<double>(k), radius);
        return out;
    }
};

}  // namespace hymm::dynamic::bench
