#include "world_generation.h"

#include <cmath>
#include <string>

namespace hymm::sim::detail
{
namespace
{
// Along-path jitter of a candidate, as a fraction of the spacing (either way).
constexpr double kAlongJitter = 0.25;
// Angular jitter of a generated polygon's vertices, as a fraction of their spacing.
constexpr double kVertexJitter = 0.3;

/** The outlines an object takes at its trajectory keys (one for a fixed object). */
std::vector<Polygon> keyOutlines(const WorldObject& obj)
{
    std::vector<Polygon> out;
    for (const auto& k : obj.trajectory) out.push_back(obj.outlineAt(k.t));
    return out;
}
}  // namespace

WorldGenerator::WorldGenerator(const World::Options& options, const ClosedPath& path)
    : o_(options), path_(path), rng_(static_cast<uint32_t>(options.seed))
{
}

Vec2 WorldGenerator::besidePath(double s, double spacing, int side, double off_min, double off_max)
{
    const double along = s + rng_.drawUniform(-kAlongJitter, kAlongJitter) * spacing;
    const double offset = rng_.drawUniform(off_min, off_max);
    const double h = path_.headingAt(along);
    return path_.pointAt(along) + side * offset * Vec2(-std::sin(h), std::cos(h));
}

Polygon WorldGenerator::randomShape()
{
    const double size = rng_.drawUniform(o_.object_size_min_m, o_.object_size_max_m);
    const double yaw = rng_.drawUniform(-M_PI, M_PI);
    Polygon local;
    if (rng_.drawUniform(0.0, 1.0) < 0.5)
    {  // a box (building, car park, container)
        const double w = size * rng_.drawUniform(0.3, 1.0);
        local = {{-size / 2, -w / 2}, {size / 2, -w / 2}, {size / 2, w / 2}, {-size / 2, w / 2}};
    }
    else
    {  // a convex polygon with 3, 5 or 6 vertices on a circle
        static constexpr int kVertexCounts[] = {3, 5, 6};
        const int k = kVertexCounts[static_cast<int>(rng_.drawUniform(0.0, 2.999))];
        for (int j = 0; j < k; ++j)
        {
            const double a = 2 * M_PI * (j + rng_.drawUniform(-kVertexJitter, kVertexJitter)) / k;
            local.emplace_back(size / 2 * std::cos(a), size / 2 * std::sin(a));
        }
    }
    return transformPolygon(local, 0, 0, yaw);
}

void WorldGenerator::addObjects(std::vector<WorldObject>& objects)
{
    const double spacing = o_.object_spacing_m;
    if (spacing <= 0) return;
    int generated = 0;
    for (double s = spacing / 2; s < path_.length(); s += spacing)
        for (int side : {1, -1})
        {
            const Vec2 c =
                besidePath(s, spacing, side, o_.object_offset_min_m, o_.object_offset_max_m);
            WorldObject obj;
            obj.outline = randomShape();
            obj.trajectory = {PoseKey{0, c.x(), c.y(), 0}};
            const Polygon global = obj.outlineAt(0);
            bool ok = boundaryDistance(global, path_.vertices()) >= o_.clearance_m;
            for (size_t i = 0; ok && i < objects.size(); ++i)
                for (const auto& other : keyOutlines(objects[i]))
                    ok = ok && polygonDistance(global, other) >= o_.object_separation_m;
            if (!ok) continue;
            obj.name = "gen_" + std::to_string(generated++);
            obj.kind = "generated";
            objects.push_back(std::move(obj));
        }
}

void WorldGenerator::addLandmarks(std::vector<Landmark>& landmarks,
                                  const std::vector<WorldObject>& objects)
{
    const double spacing = o_.landmark_spacing_m;
    if (spacing <= 0) return;
    std::vector<Polygon> outlines;
    for (const auto& obj : objects)
        for (auto& p : keyOutlines(obj)) outlines.push_back(std::move(p));
    for (double s = spacing / 2; s < path_.length(); s += spacing)
        for (int side : {1, -1})
        {
            Landmark lm;
            lm.position =
                besidePath(s, spacing, side, o_.landmark_offset_min_m, o_.landmark_offset_max_m);
            lm.radius = rng_.drawUniform(o_.landmark_radius_min_m, o_.landmark_radius_max_m);
            bool ok = path_.distanceTo(lm.position) - lm.radius >= o_.clearance_m;
            for (size_t i = 0; ok && i < outlines.size(); ++i)
                ok = pointPolygonDistance(lm.position, outlines[i]) - lm.radius >=
                     o_.landmark_separation_m;
            for (size_t i = 0; ok && i < landmarks.size(); ++i)
                ok = (landmarks[i].position - lm.position).norm() >= o_.landmark_separation_m;
            if (ok) landmarks.push_back(lm);
        }
}

}  // namespace hymm::sim::detail
