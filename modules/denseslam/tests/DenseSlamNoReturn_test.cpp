// DenseSlam on the slow-motion scene without the wall behind the parked car (thesis
// 6.3.3; configs/sim/ch6_dynamic_slow_open.ini: the car moves 8 m west after the first
// lap), simulated in process and checked against the simulator's ground truth. After
// the car moves away its old place is seen against nothing: the beams through it
// return nothing (LaserSimulator flags them invalid), so only [HybridMetricMap]
// no_return_free_range_m can empty it:
//  - off (the default), the particle layer (Sec. 4.2) keeps the car's old place and the
//    occupancy layer (Sec. 4.1) keeps it occupied;
//  - on, the free-space step of Sec. 4.2.2 runs along the no-return beams and the old
//    place loses its particles and its occupied cells, while what stayed keeps its
//    particles and what appeared is picked up (the step's protection keeps surfaces a
//    nearer return or a grazing view explains).
#include "sim_feed.h"

#include <gtest/gtest.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/sim/Simulator.h>
#include <hymm/sim/geometry.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <algorithm>
#include <functional>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using hymm::denseslam::DenseSlam;
using hymm::denseslam::testing::object;
using hymm::denseslam::testing::run;
using hymm::sim::Polygon;
using hymm::sim::Vec2;

const std::string kScenario =
    std::string(HYMM_SOURCE_DIR) + "/configs/sim/ch6_dynamic_slow_open.ini";

// The map reaches 25 m (the laser 40 m): no-return beams are free space up to 25 m.
constexpr double kMapRange = 25.0;

// As DenseSlam_dynamic_test.cpp, with the no-return free range under test.
std::string slamConfig(double no_return_free_range_m)
{
    return hymm::denseslam::testing::dynamicSceneConfig(
        "occupancy,particles", kMapRange,
        "no_return_free_range_m = " + std::to_string(no_return_free_range_m) + "\n");
}

size_t countNear(const std::vector<Vec2>& pts, const Polygon& outline, double grow)
{
    return static_cast<size_t>(std::count_if(
        pts.begin(), pts.end(),
        [&](const Vec2& p) { return hymm::sim::pointPolygonDistance(p, outline) <= grow; }));
}

// "Inside the true outline grown by" this: covers the laser and pose noise of the
// returns that built the particles (as DenseSlam_dynamic_test.cpp).
constexpr double kGrow = 0.3;

/** Heavy particles (w > 0.8) and the occupancy of the cells on an outline. */
struct MapSnapshot
{
    std::vector<Vec2> heavy;
    mrpt::maps::COccupancyGridMap2D grid;

    static MapSnapshot of(DenseSlam& slam)
    {
        slam.refreshRegions();
        MapSnapshot m;
        mrpt::maps::CPointsMapXYZI particles;
        slam.hybridMap()->renderLayer("particles", *slam.partition(), particles);
        for (size_t i = 0; i < particles.size(); ++i)
            if (particles.getPointIntensity(i) > 0.8f)
                m.heavy.emplace_back(particles.getPointsBufferRef_x()[i],
                                     particles.getPointsBufferRef_y()[i]);
        slam.hybridMap()->renderOccupancy(*slam.partition(), 0.1, m.grid);
        return m;
    }

    /** Cells whose centre lies within kGrow of `outline` and that hold evidence
     *  (P != 0.5): how many, and how many of them read occupied (P > 0.8). */
    std::pair<size_t, size_t> cellsNear(const Polygon& outline) const
    {
        size_t known = 0, occupied = 0;
        for (unsigned cy = 0; cy < grid.getSizeY(); ++cy)
            for (unsigned cx = 0; cx < grid.getSizeX(); ++cx)
            {
                const Vec2 c(grid.idx2x(cx), grid.idx2y(cy));
                if (hymm::sim::pointPolygonDistance(c, outline) > kGrow) continue;
                const float p = grid.getCell(static_cast<int>(cx), static_cast<int>(cy));
                if (std::abs(p - 0.5f) < 1e-3f) continue;
                ++known;
                occupied += p > 0.8f;
            }
        return {known, occupied};
    }
};

struct Outcome
{
    MapSnapshot before, after;
    DenseSlam::Stats stats;
};

Outcome simulate(const hymm::sim::Scenario& s, double t_change, double no_return_free_range_m)
{
    mrpt::config::CConfigFileMemory cfg(slamConfig(no_return_free_range_m));
    DenseSlam slam = DenseSlam::fromConfig(cfg);
    Outcome out;
    run(s, slam,
        [&](double t)
        {
            if (t < t_change && t + s.laser.period_s >= t_change) out.before = MapSnapshot::of(slam);
        });
    out.after = MapSnapshot::of(slam);
    out.stats = slam.stats();
    return out;
}

TEST(DenseSlamNoReturn, NoReturnBeamsEmptyTheCarsOldPlaceSeenAgainstNothing)
{
    const auto s = hymm::sim::Scenario::fromFile(kScenario);
    const hymm::sim::World world = hymm::sim::World::build(s.world, nullptr);
    const auto& car = object(world, "car");
    const double t_change = car.trajectory.back().t;
    const Polygon car_old = car.outlineAt(0), car_new = car.outlineAt(t_change);
    for (const auto& o : world.objects()) ASSERT_NE(o.name, "wall_south");  // nothing behind the car

    const Outcome off = simulate(s, t_change, 0.0);
    const Outcome on = simulate(s, t_change, kMapRange);

    const size_t off_before = countNear(off.before.heavy, car_old, kGrow);
    const size_t off_after = countNear(off.after.heavy, car_old, kGrow);
    const size_t on_before = countNear(on.before.heavy, car_old, kGrow);
    const size_t on_after = countNear(on.after.heavy, car_old, kGrow);
    const auto [off_cells_before, off_occ_before] = off.before.cellsNear(car_old);
    const auto [off_cells_after, off_occ_after] = off.after.cellsNear(car_old);
    const auto [on_cells_before, on_occ_before] = on.before.cellsNear(car_old);
    const auto [on_cells_after, on_occ_after] = on.after.cellsNear(car_old);
    std::cout << "[ no-return ] heavy particles (w > 0.8) within " << kGrow
              << " m of the car's old outline, before -> after the move: off " << off_before
              << " -> " << off_after << ", on " << on_before << " -> " << on_after << "\n"
              << "[ no-return ] occupied cells (P > 0.8) / cells with evidence there: off "
              << off_occ_before << "/" << off_cells_before << " -> " << off_occ_after << "/"
              << off_cells_after << ", on " << on_occ_before << "/" << on_cells_before << " -> "
              << on_occ_after << "/" << on_cells_after << "\n";

    // The pipeline counts the beams it used as free space; the simulated laser has no
    // failed readings.
    EXPECT_EQ(off.stats.no_return_beams, 0u);
    EXPECT_GT(on.stats.no_return_beams, 1000u);
    EXPECT_EQ(on.stats.failed_readings, 0u);
    EXPECT_EQ(on.stats.returns_stored + on.stats.returns_outside,
              off.stats.returns_stored + off.stats.returns_outside);

    // Before the move both maps hold the parked car.
    EXPECT_GT(off_before, 500u);
    EXPECT_GT(on_before, 500u);
    EXPECT_GT(off_occ_before, 20u);
    EXPECT_GT(on_occ_before, 20u);

    // Off: nothing returns from the old place any more, and nothing else says it is
    // empty: the particles and the occupied cells stay.
    EXPECT_GE(off_after, off_before * 8 / 10);
    EXPECT_GE(off_occ_after, off_occ_before * 8 / 10);
    // On: the no-return beams free it.
    EXPECT_LE(on_after, on_before / 50);
    EXPECT_LE(on_occ_after, on_occ_before / 10);

    // With the option on, what stayed keeps its particles (the protection of the
    // free-space step) and what appeared is picked up.
    hymm::dense::OutlineMetricsOptions cov;
    cov.sample_step_m = 0.1;
    cov.coverage_radius_m = 0.5;
    const Polygon west = object(world, "west").outlineAt(0);
    const double c_before = hymm::dense::evaluateOutlines(on.before.heavy, {west}, cov).coverage;
    const double c_after = hymm::dense::evaluateOutlines(on.after.heavy, {west}, cov).coverage;
    const double c_off = hymm::dense::evaluateOutlines(off.after.heavy, {west}, cov).coverage;
    std::cout << "[ no-return ] west building outline coverage by heavy particles: on "
              << c_before << " -> " << c_after << ", off at the end " << c_off << "\n";
    EXPECT_GT(c_before, 0.2);
    EXPECT_GE(c_after, 0.9 * c_before);
    EXPECT_GE(c_after, 0.9 * c_off);
    const size_t new_on = countNear(on.after.heavy, car_new, kGrow);
    const size_t new_off = countNear(off.after.heavy, car_new, kGrow);
    std::cout << "[ no-return ] heavy particles on the car's new outline at the end: off "
              << new_off << ", on " << new_on << "\n";
    EXPECT_GT(new_on, 200u);
    EXPECT_GE(new_on, new_off * 8 / 10);
}

}  // namespace
