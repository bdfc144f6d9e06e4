#include "hymm/sim/World.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "world_generation.h"

namespace hymm::sim
{
Eigen::Vector3d WorldObject::poseAt(double t) const
{
    const auto& k = trajectory;
    const auto asVec = [](const PoseKey& p) { return Eigen::Vector3d(p.x, p.y, p.phi); };
    if (k.size() == 1 || t <= k.front().t) return asVec(k.front());
    if (t >= k.back().t) return asVec(k.back());
    const auto it = std::upper_bound(k.begin(), k.end(), t,
                                     [](double tt, const PoseKey& p) { return tt < p.t; });
    const PoseKey& b = *it;
    const PoseKey& a = *(it - 1);
    const double u = (t - a.t) / (b.t - a.t);
    return {a.x + u * (b.x - a.x), a.y + u * (b.y - a.y),
            mrpt::math::wrapToPi(a.phi + u * mrpt::math::wrapToPi(b.phi - a.phi))};
}

Polygon WorldObject::outlineAt(double t) const
{
    const Eigen::Vector3d p = poseAt(t);
    return transformPolygon(outline, p[0], p[1], p[2]);
}

std::optional<WorldSnapshot::Hit> WorldSnapshot::castRay(const Vec2& origin, double angle,
                                                         double max_range, long skip_landmark) const
{
    const Vec2 d(std::cos(angle), std::sin(angle));
    std::optional<Hit> best;
    const auto consider = [&](const std::optional<double>& t, bool is_landmark, long id)
    {
        if (t && *t < max_range && (!best || *t < best->range)) best = Hit{*t, is_landmark, id};
    };
    for (const auto& lm : landmarks)
        if (lm.id != skip_landmark)
            consider(rayCircle(origin, d, lm.position, lm.radius), true, lm.id);
    for (const auto& [id, poly] : objects) consider(rayPolygon(origin, d, poly), false, id);
    return best;
}

double SurfaceProperties::objectValue(long object_id, const Vec2& p) const
{
    const auto it = objects.find(object_id);
    return it != objects.end() ? it->second : field.at(p);
}

World::World(std::vector<Landmark> landmarks, std::vector<WorldObject> objects,
             std::optional<double> landmark_property, PropertyField field)
    : landmarks_(std::move(landmarks)), objects_(std::move(objects))
{
    properties_.field = field;
    properties_.landmarks = landmark_property;
    std::set<long> ids;
    for (const auto& obj : objects_)
    {
        if (!ids.insert(obj.id).second)
            throw std::invalid_argument("World: object id " + std::to_string(obj.id) +
                                        " is used more than once");
        if (obj.property) properties_.objects[obj.id] = *obj.property;
    }
    for (const auto& lm : landmarks_)
        if (lm.carrier >= 0 && !carrier(lm))
            throw std::invalid_argument("World: landmark " + std::to_string(lm.id) +
                                        " is carried by object " + std::to_string(lm.carrier) +
                                        ", which does not exist");
}

const WorldObject* World::carrier(const Landmark& lm) const
{
    if (lm.carrier < 0) return nullptr;
    const auto it = std::find_if(objects_.begin(), objects_.end(),
                                 [&](const WorldObject& o) { return o.id == lm.carrier; });
    return it == objects_.end() ? nullptr : &*it;
}

double World::propertyAt(const WorldSnapshot::Hit& hit, const Vec2& p) const
{
    return hit.landmark ? properties_.landmarkValue(p) : properties_.objectValue(hit.id, p);
}

World World::build(const Options& o, const ClosedPath* path)
{
    std::vector<WorldObject> objects = o.objects;
    std::vector<Landmark> landmarks = o.landmarks;
    if (path)
    {
        // One generator for both passes, objects first so that landmarks avoid them.
        detail::WorldGenerator gen(o, *path);
        gen.addObjects(objects);
        gen.addLandmarks(landmarks, objects);
    }
    for (size_t i = 0; i < objects.size(); ++i) objects[i].id = static_cast<long>(i);
    // Landmarks the objects carry come last: every other id stays what it was.
    for (const auto& obj : objects)
        for (const auto& c : obj.landmarks)
        {
            const Eigen::Vector3d p = obj.poseAt(-std::numeric_limits<double>::infinity());
            const Vec2 at = transformPolygon({c.offset}, p[0], p[1], p[2]).front();
            landmarks.push_back(Landmark{0, at, c.radius, obj.id, c.offset});
        }
    for (size_t i = 0; i < landmarks.size(); ++i) landmarks[i].id = static_cast<long>(i);
    return World(std::move(landmarks), std::move(objects), o.landmark_property,
                 o.property_field.value_or(PropertyField{}));
}

WorldSnapshot World::snapshot(double t, const Vec2& centre, double radius) const
{
    WorldSnapshot s;
    for (const auto& lm : landmarks_)
    {
        Landmark at = lm;
        if (const WorldObject* obj = carrier(lm))
        {
            // A carried landmark is where its object is, and absent when it is.
            if (!obj->presentAt(t)) continue;
            const Eigen::Vector3d p = obj->poseAt(t);
            at.position = transformPolygon({lm.offset}, p[0], p[1], p[2]).front();
        }
        if ((at.position - centre).norm() <= radius + at.radius) s.landmarks.push_back(at);
    }
    for (const auto& obj : objects_)
    {
        if (!obj.presentAt(t)) continue;
        Polygon poly = obj.outlineAt(t);
        Vec2 c;
        double r = 0;
        boundingCircle(poly, c, r);
        if ((c - centre).norm() <= radius + r) s.objects.emplace_back(obj.id, std::move(poly));
    }
    return s;
}

}  // namespace hymm::sim
