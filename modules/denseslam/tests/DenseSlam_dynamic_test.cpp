// DenseSlam on the shortened slow-motion scene (thesis 6.3.3, Fig. 6.10;
// configs/sim/ch6_dynamic_slow_short.ini), simulated in process and checked against the
// simulator's ground truth:
//  - the particle layer (Sec. 4.2, a dynamic layer) forgets the object removed from the
//    middle and the parked car's old place once they are seen again, keeps what stayed
//    and picks up what appeared; the points layer (not dynamic) keeps the old returns;
//  - the property layer (Sec. 4.5) recovers each object's simulated surface property
//    from the laser intensities, with a standard deviation that is honest and shrinks
//    with more observations.
#include "sim_feed.h"

#include <gtest/gtest.h>
#include <hymm/dense/ScalarField.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/sim/Simulator.h>
#include <hymm/sim/geometry.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
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
    std::string(HYMM_SOURCE_DIR) + "/configs/sim/ch6_dynamic_slow_short.ini";

// The map is limited to 25 m (the laser reaches 40 m: farther returns are free space only).
std::string slamConfig(const std::string& layers)
{
    return hymm::denseslam::testing::dynamicSceneConfig(layers, 25.0, R"([PropertyLayer]
cell_size_m = 0.2
; the simulated intensity noise (std_intensity in the scenario)
default_value_std = 4
)");
}

DenseSlam makeSlam(const std::string& layers)
{
    mrpt::config::CConfigFileMemory cfg(slamConfig(layers));
    return DenseSlam::fromConfig(cfg);
}

/** Heavy particles (w > 0.8) and raw returns of the map at the current estimates. */
struct MapSnapshot
{
    std::vector<Vec2> heavy, points;

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
        mrpt::maps::CSimplePointsMap pts;
        slam.hybridMap()->renderPoints(*slam.partition(), pts);
        m.points = hymm::dense::pointsOf(pts);
        return m;
    }
};

size_t countNear(const std::vector<Vec2>& pts, const Polygon& outline, double grow)
{
    return static_cast<size_t>(std::count_if(
        pts.begin(), pts.end(),
        [&](const Vec2& p) { return hymm::sim::pointPolygonDistance(p, outline) <= grow; }));
}

// "Inside the true outline grown by" this: covers the laser and pose noise of the
// returns that built the particles.
constexpr double kGrow = 0.3;

TEST(DenseSlamDynamic, ParticleLayerForgetsWhatLeftAndKeepsWhatStayed)
{
    const auto s = hymm::sim::Scenario::fromFile(kScenario);
    const hymm::sim::World world = hymm::sim::World::build(s.world, nullptr);
    const auto& middle = object(world, "middle");
    const auto& car = object(world, "car");
    const double t_change = middle.present_to;
    ASSERT_EQ(car.trajectory.back().t, t_change);
    const Polygon middle_outline = middle.outlineAt(0);
    const Polygon car_old = car.outlineAt(0), car_new = car.outlineAt(t_change);
    // Objects there all along (the wall is where the car parks; west is a building).
    const std::vector<std::string> stayed = {"west", "wall_south"};

    DenseSlam slam = makeSlam("points,particles");
    MapSnapshot before;
    run(s, slam,
        [&](double t)
        {
            if (t < t_change && t + s.laser.period_s >= t_change) before = MapSnapshot::of(slam);
        });
    const MapSnapshot after = MapSnapshot::of(slam);
    ASSERT_FALSE(before.heavy.empty());

    // Before the change both the middle object and the car are in the particle layer.
    const size_t mid_before = countNear(before.heavy, middle_outline, kGrow);
    const size_t car_before = countNear(before.heavy, car_old, kGrow);
    EXPECT_GT(mid_before, 100u);
    EXPECT_GT(car_before, 500u);

    // Seen again after the change, their places hold (almost) no heavy particle
    // (measured: 8 of 130 near the middle object, 6 %).
    EXPECT_LE(countNear(after.heavy, middle_outline, kGrow), mid_before / 10)
        << "before " << mid_before;
    EXPECT_LE(countNear(after.heavy, car_old, kGrow), car_before / 20) << "before " << car_before;

    // The points layer is not dynamic: the old returns are still there (so the map has
    // not drifted off the outlines, and the particle test above can tell the difference).
    const size_t mid_pts = countNear(before.points, middle_outline, kGrow);
    const size_t car_pts = countNear(before.points, car_old, kGrow);
    EXPECT_GT(mid_pts, 30u);
    EXPECT_GT(car_pts, 200u);
    EXPECT_GE(countNear(after.points, middle_outline, kGrow), mid_pts * 8 / 10);
    EXPECT_GE(countNear(after.points, car_old, kGrow), car_pts * 8 / 10);

    // What stayed keeps its particles: as much of its outline covered as before.
    hymm::dense::OutlineMetricsOptions cov;
    cov.sample_step_m = 0.1;
    cov.coverage_radius_m = 0.5;
    for (const auto& name : stayed)
    {
        const Polygon outline = object(world, name).outlineAt(0);
        const double c_before =
            hymm::dense::evaluateOutlines(before.heavy, {outline}, cov).coverage;
        const double c_after = hymm::dense::evaluateOutlines(after.heavy, {outline}, cov).coverage;
        EXPECT_GT(c_before, 0.2) << name;
        EXPECT_GE(c_after, 0.9 * c_before) << name;
    }

    // What appeared is picked up: the car at its new place, the new container.
    EXPECT_EQ(countNear(before.heavy, car_new, kGrow), 0u);
    EXPECT_GT(countNear(after.heavy, car_new, kGrow), 200u);
    EXPECT_GT(countNear(after.heavy, object(world, "new_left").outlineAt(t_change), kGrow), 200u);
}

/** A surface of the simulated world: an object (every outline it takes) or a landmark
 *  trunk, with its true property at a point. */
struct Surface
{
    std::string name;
    std::vector<Polygon> outlines;  // objects
    Vec2 centre = Vec2::Zero();     // landmarks
    double radius = 0;
    std::function<double(const Vec2&)> truth;

    double distance(const Vec2& p) const
    {
        if (outlines.empty()) return std::max(0.0, (p - centre).norm() - radius);
        double d = 1e9;
        for (const auto& o : outlines) d = std::min(d, hymm::sim::pointPolygonDistance(p, o));
        return d;
    }
};

std::vector<Surface> surfacesOf(const hymm::sim::World& world)
{
    std::vector<Surface> out;
    const auto& props = world.properties();
    for (const auto& o : world.objects())
    {
        Surface s;
        s.name = o.name;
        for (const auto& k : o.trajectory) s.outlines.push_back(o.outlineAt(k.t));
        const long id = o.id;
        s.truth = [&props, id](const Vec2& p) { return props.objectValue(id, p); };
        out.push_back(std::move(s));
    }
    for (const auto& lm : world.landmarks())
    {
        Surface s;
        s.name = "landmarks";
        s.centre = lm.position;
        s.radius = lm.radius;
        s.truth = [&props](const Vec2& p) { return props.landmarkValue(p); };
        out.push_back(std::move(s));
    }
    return out;
}

/** Rendered property cells near one kind of surface. */
struct SurfaceCells
{
    std::vector<double> mean, stddev, truth;

    /** Inverse-variance mean of (mean - truth): 0 when the cells recover the truth. */
    double combinedResidual() const
    {
        double info = 0, w = 0;
        for (size_t i = 0; i < mean.size(); ++i)
        {
            info += 1 / (stddev[i] * stddev[i]);
            w += (mean[i] - truth[i]) / (stddev[i] * stddev[i]);
        }
        return w / info;
    }
    double combinedStd() const
    {
        double info = 0;
        for (double s : stddev) info += 1 / (s * s);
        return 1 / std::sqrt(info);
    }
    void append(const SurfaceCells& o)
    {
        mean.insert(mean.end(), o.mean.begin(), o.mean.end());
        stddev.insert(stddev.end(), o.stddev.begin(), o.stddev.end());
        truth.insert(truth.end(), o.truth.begin(), o.truth.end());
    }
    /** RMS of (mean - truth) / stddev: 1 when the layer's stddev is honest. */
    double rmsNormalisedError() const
    {
        double s = 0;
        for (size_t i = 0; i < mean.size(); ++i) s += std::pow((mean[i] - truth[i]) / stddev[i], 2);
        return std::sqrt(s / static_cast<double>(mean.size()));
    }
};

// A rendered cell belongs to the surface within kNear of its centre when every other
// surface is farther than kClear (returns of a neighbour cannot reach it).
constexpr double kNear = 0.3;
constexpr double kClear = 1.5;

std::map<std::string, SurfaceCells> propertyCells(DenseSlam& slam,
                                                  const std::vector<Surface>& surfaces)
{
    slam.refreshRegions();
    hymm::dense::ScalarField mean, sd;
    slam.hybridMap()->renderProperty(*slam.partition(), 0.2, mean, sd);
    std::map<std::string, SurfaceCells> out;
    for (int iy = 0; iy < mean.sizeY(); ++iy)
        for (int ix = 0; ix < mean.sizeX(); ++ix)
        {
            if (std::isnan(mean.values(iy, ix))) continue;
            const Vec2 c = mean.cellCentre(ix, iy);
            const Surface* nearest = nullptr;
            double d1 = 1e9, d2 = 1e9;
            for (const auto& s : surfaces)
            {
                const double d = s.distance(c);
                if (d < d1)
                {
                    d2 = d1;
                    d1 = d;
                    nearest = &s;
                }
                else
                    d2 = std::min(d2, d);
            }
            if (!nearest || d1 > kNear || d2 < kClear) continue;
            auto& cells = out[nearest->name];
            cells.mean.push_back(mean.values(iy, ix));
            cells.stddev.push_back(sd.values(iy, ix));
            cells.truth.push_back(nearest->truth(c));
        }
    return out;
}

TEST(DenseSlamProperty, RecoversEachSurfacesSimulatedProperty)
{
    const auto s = hymm::sim::Scenario::fromFile(kScenario);
    ASSERT_TRUE(s.laser.intensity);
    const double t_lap = object(hymm::sim::World::build(s.world, nullptr), "middle").present_to;
    const hymm::sim::Simulator truth(s);  // the world with its generated landmarks
    const auto surfaces = surfacesOf(truth.world());

    DenseSlam slam = makeSlam("property");
    std::map<std::string, SurfaceCells> first;
    run(s, slam,
        [&](double t)
        {
            if (t < t_lap && t + s.laser.period_s >= t_lap) first = propertyCells(slam, surfaces);
        });
    const auto last = propertyCells(slam, surfaces);

    // Every surface a region holds, except the east building that no region reaches:
    // objects with their own value, the landmarks, and the wall on the smooth field.
    for (const char* name :
         {"west", "middle", "car", "new_left", "new_right", "wall_south", "landmarks"})
    {
        SCOPED_TRACE(name);
        ASSERT_TRUE(last.count(name));
        const SurfaceCells& c = last.at(name);
        ASSERT_GE(c.mean.size(), 15u);  // measured: 18 for the middle object, the fewest
        // The value the cells agree on is the true one within the noise of their
        // combination (intensity sigma 4; under 1 takes more than 16 returns).
        EXPECT_NEAR(c.combinedResidual(), 0.0, 4 * c.combinedStd());
        EXPECT_LT(c.combinedStd(), 1.0);
    }

    // The layer's standard deviation is honest: cell errors over their stated sigma
    // have unit RMS (all cells pooled).
    SurfaceCells all;
    for (const auto& kv : last) all.append(kv.second);
    ASSERT_GT(all.mean.size(), 500u);
    EXPECT_NEAR(all.rmsNormalisedError(), 1.0, 0.15);

    // More observations, smaller uncertainty: what the second lap saw again is known
    // better than after the first; the middle object, gone, gets no new values.
    for (const char* name : {"west", "car", "wall_south", "landmarks"})
    {
        ASSERT_TRUE(first.count(name)) << name;
        EXPECT_LT(last.at(name).combinedStd(), 0.85 * first.at(name).combinedStd()) << name;
        EXPECT_NEAR(first.at(name).combinedResidual(), 0.0, 4 * first.at(name).combinedStd())
            << name;
    }
    ASSERT_TRUE(first.count("middle"));
    EXPECT_NEAR(last.at("middle").combinedStd(), first.at("middle").combinedStd(),
                0.05 * first.at("middle").combinedStd());
}

}  // namespace
