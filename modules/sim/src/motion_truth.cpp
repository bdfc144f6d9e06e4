#include "hymm/sim/motion_truth.h"

#include <cmath>
#include <set>

namespace hymm::sim
{
const char* changeName(ChangedArea::Change c)
{
    switch (c)
    {
        case ChangedArea::Change::Removed: return "removed";
        case ChangedArea::Change::Added: return "added";
        case ChangedArea::Change::MovedFrom: return "moved_from";
        case ChangedArea::Change::MovedTo: return "moved_to";
    }
    return "?";
}

std::vector<ChangedArea> changedAreas(const World& world, double t_before, double t_after)
{
    std::vector<ChangedArea> out;
    for (const auto& o : world.objects())
    {
        const bool a = o.presentAt(t_before), b = o.presentAt(t_after);
        auto area = [&](ChangedArea::Change c, double t) {
            out.push_back({o.id, o.name, c, o.outlineAt(t)});
        };
        if (a && !b)
            area(ChangedArea::Change::Removed, t_before);
        else if (!a && b)
            area(ChangedArea::Change::Added, t_after);
        else if (a && b)
        {
            const Eigen::Vector3d d = o.poseAt(t_after) - o.poseAt(t_before);
            if (d.head<2>().norm() > 1e-3 || std::abs(std::remainder(d[2], 2 * M_PI)) > 1e-3)
            {
                area(ChangedArea::Change::MovedFrom, t_before);
                area(ChangedArea::Change::MovedTo, t_after);
            }
        }
    }
    return out;
}

std::vector<Polygon> sweptFootprints(const World& world, double t0, double t1, double dt)
{
    std::vector<Polygon> out;
    if (!(dt > 0)) return out;
    for (const auto& o : world.objects())
    {
        if (!o.moves()) continue;
        const long n = static_cast<long>(std::floor((t1 - t0) / dt + 1e-9));
        for (long k = 0; k <= n; ++k)
        {
            const double t = t0 + static_cast<double>(k) * dt;
            if (o.presentAt(t)) out.push_back(o.outlineAt(t));
        }
    }
    return out;
}

std::vector<Polygon> staticOutlines(const World& world)
{
    std::vector<Polygon> out;
    for (const auto& o : world.objects())
        if (o.isStatic()) out.push_back(o.outlineAt(0.0));
    return out;
}

std::vector<Vec2> movingObjectHits(const World& world, double t, const Eigen::Vector3d& sensor,
                                   double fov, double resolution, double max_range)
{
    std::set<long> moving;
    for (const auto& o : world.objects())
        if (o.moves()) moving.insert(o.id);
    std::vector<Vec2> out;
    if (moving.empty() || !(resolution > 0)) return out;
    const Vec2 origin = sensor.head<2>();
    const WorldSnapshot snap = world.snapshot(t, origin, max_range);
    const long n = static_cast<long>(std::floor(fov / resolution + 1e-9));
    for (long k = 0; k <= n; ++k)
    {
        const double a = sensor[2] - 0.5 * fov + static_cast<double>(k) * resolution;
        const auto hit = snap.castRay(origin, a, max_range);
        if (hit && !hit->landmark && moving.count(hit->id))
            out.push_back(origin + hit->range * Vec2(std::cos(a), std::sin(a)));
    }
    return out;
}

}  // namespace hymm::sim
