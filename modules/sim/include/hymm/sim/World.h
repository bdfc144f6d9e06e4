/**
 * @file World.h
 * @brief The simulated 2D world: point landmarks (poles, trees: circles with a radius)
 *        and polygonal objects (walls, buildings, cars), some of which move or appear
 *        and disappear, plus the ray casting the sensors use.
 *
 * Configuration: section [World] sets landmark and object generation; every section
 * named [Object_<name>] adds one object (keys below). Generated items are placed along
 * both sides of the vehicle's path from their own seed (World::Options::seed), so the
 * world stays the same when the noise seed of a Monte Carlo run changes.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hymm/sim/geometry.h"

namespace hymm::sim
{
class ClosedPath;

/** A pole or tree: what the landmark detector reports (its centre) and what the laser
 *  sees (its circular trunk). A landmark may be carried by an object (a reflector on a
 *  parked car): it then moves with the object and is absent whenever the object is. */
struct Landmark
{
    long id = 0;
    Vec2 position = Vec2::Zero();  //!< centre [m]; carried: at the object's first pose
    double radius = 0.2;           //!< [m]
    long carrier = -1;             //!< id of the object carrying it (-1: fixed)
    Vec2 offset = Vec2::Zero();    //!< carried: centre in the object's frame [m]
};

/** A landmark fixed to an object, in the object's frame (WorldObject::landmarks). */
struct CarriedLandmark
{
    Vec2 offset = Vec2::Zero();  //!< centre in the object's frame [m]
    double radius = 0.2;         //!< [m]
};

/** A smooth scalar field over the plane: v0 + gx x + gy y. */
struct PropertyField
{
    double v0 = 0;  //!< value at the origin [property units]
    double gx = 0;  //!< gradient along x [units/m]
    double gy = 0;  //!< gradient along y [units/m]
    double at(const Vec2& p) const { return v0 + gx * p.x() + gy * p.y(); }
};

/**
 * The true scalar property of every surface (thesis Sec. 4.5: a multi-layer map holds
 * any property of the environment, not only occupancy), which the laser reports as
 * the intensity of each return (LaserSimulator::Options::intensity). An object with
 * its own `property` has that value all over its outline; landmark trunks share
 * [World] landmark_property; every other surface takes the field at the point hit.
 */
struct SurfaceProperties
{
    PropertyField field;              //!< surfaces without their own value
    std::optional<double> landmarks;  //!< every landmark trunk; nullopt: the field
    std::map<long, double> objects;   //!< object id -> its own value

    double objectValue(long object_id, const Vec2& p) const;
    double landmarkValue(const Vec2& p) const { return landmarks ? *landmarks : field.at(p); }
};

/** Pose of an object at time `t` [s since the start of the run]; phi in radians. */
struct PoseKey
{
    double t = 0;
    double x = 0, y = 0, phi = 0;
};

/**
 * A polygonal object. Its outline is given in its own frame and placed by a pose that
 * is piecewise-linear in time between the keys of `trajectory` (held before the first
 * and after the last key); a single key is a fixed object. Fast dynamic objects move
 * while observed; slow ones are moved (two keys close in time), added or removed
 * (`appear_s`/`disappear_s`) between two visits.
 *
 * Ini section [Object_<name>]:
 *   kind = building          ; free label (wall, car, person, ...)
 *   shape = box              ; box | polygon
 *   size = 12 8              ; box: length (along the object's x) and width [m]
 *   vertices = 0 0 10 0 0 6  ; polygon: x y pairs in the object frame [m]
 *   pose = 20 30 15          ; x y yaw_deg of a fixed object
 *   trajectory = 0 -10 5 0  20 10 5 0   ; or: t x y yaw_deg keys (t in s from the start)
 *   appear_s = 100           ; optional: absent before this time [s]
 *   disappear_s = 100        ; optional: absent from this time on [s]
 *   landmarks = 2 0.9 0.1    ; optional: x y radius of point landmarks it carries
 *                            ; (object frame; e.g. a reflector), see World::build
 */
struct WorldObject
{
    long id = 0;
    std::string name;
    std::string kind = "object";
    Polygon outline;                  //!< object frame, counter-clockwise
    std::vector<PoseKey> trajectory;  //!< at least one key, strictly increasing times
    double present_from = -std::numeric_limits<double>::infinity();
    double present_to = std::numeric_limits<double>::infinity();
    std::optional<double> property;  //!< own surface property (SurfaceProperties)
    std::vector<CarriedLandmark> landmarks;  //!< point landmarks fixed to the object

    bool moves() const { return trajectory.size() > 1; }
    bool presentAt(double t) const { return t >= present_from && t < present_to; }
    bool isStatic() const { return !moves() && std::isinf(present_from) && std::isinf(present_to); }
    Eigen::Vector3d poseAt(double t) const;
    Polygon outlineAt(double t) const;

    /** Parses [section] (see above); throws naming section, key and value. */
    static WorldObject fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                  const std::string& section, long id);
    /** Writes the object back as a polygon section. */
    void toConfig(mrpt::config::CConfigFileBase& cfg, const std::string& section) const;
};

/** The world as it is at one instant, restricted to a disc around a sensor. */
class WorldSnapshot
{
public:
    struct Hit
    {
        double range = 0;       //!< [m]
        bool landmark = false;  //!< a landmark's trunk, else an object's outline
        long id = -1;           //!< id of the landmark or object hit
    };

    /** Nearest hit of the ray from `origin` at global angle `angle` closer than
     *  `max_range`, ignoring the landmark `skip_landmark` (-1: none). */
    std::optional<Hit> castRay(const Vec2& origin, double angle, double max_range,
                               long skip_landmark = -1) const;

    std::vector<Landmark> landmarks;
    std::vector<std::pair<long, Polygon>> objects;  //!< (object id, global outline)
};

class World
{
public:
    struct Options : public mrpt::config::CLoadableOptions
    {
        std::vector<Landmark> landmarks;     //!< explicit: `landmarks = x y radius ...`
        std::vector<WorldObject> objects;    //!< from the [Object_<name>] sections
        double landmark_spacing_m = 0;       //!< along-path landmark spacing (0: none)
        double landmark_offset_min_m = 3;    //!< lateral distance of the centre from the path
        double landmark_offset_max_m = 12;   //!< [m]
        double landmark_radius_min_m = 0.1;  //!< trunk radius range [m]
        double landmark_radius_max_m = 0.4;
        double landmark_separation_m = 4;  //!< min distance between generated landmarks
                                           //!< and from them to any object [m]
        double object_spacing_m = 0;       //!< along-path object spacing (0: none)
        double object_offset_min_m = 8;    //!< lateral distance of the centre from the path
        double object_offset_max_m = 20;   //!< [m]
        double object_size_min_m = 3;      //!< generated object diameter range [m]
        double object_size_max_m = 12;
        double object_separation_m = 4;  //!< min gap between objects [m]
        double clearance_m = 3;          //!< min gap between generated items and path [m]
        long seed = 1;                   //!< seed of the generation (not of the noise)
        /** Surface property of every landmark trunk (`landmark_property`); nullopt:
         *  the field. Written back only when set. */
        std::optional<double> landmark_property;
        /** `property_field = v0 gx gy` for surfaces without their own value; nullopt
         *  (the default): 0 everywhere. Written back only when set. */
        std::optional<PropertyField> property_field;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();

        /** Reads [World] and every [Object_<name>] section (ids in name order). */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                              const std::string& section) const override;
    };

    /** Prefix of the object sections. */
    static constexpr const char* kObjectSectionPrefix = "Object_";

    /** Objects need distinct ids and a carried landmark an existing carrier (throws
     *  std::invalid_argument otherwise); `landmark_property` and `field` complete the
     *  surface properties (the objects bring their own). */
    World(std::vector<Landmark> landmarks, std::vector<WorldObject> objects,
          std::optional<double> landmark_property = std::nullopt, PropertyField field = {});

    /** The configured landmarks and objects plus those generated along `path` (none
     *  when `path` is null). Landmark ids are 0..n-1, object ids 0..m-1; the landmarks
     *  objects carry come last (so adding one leaves every other id unchanged). */
    static World build(const Options& options, const ClosedPath* path);

    /** Everything present at time `t` whose bounding circle reaches the disc
     *  (`centre`, `radius`); carried landmarks where their object is at `t`. */
    WorldSnapshot snapshot(double t, const Vec2& centre, double radius) const;

    const std::vector<Landmark>& landmarks() const { return landmarks_; }
    const std::vector<WorldObject>& objects() const { return objects_; }
    const SurfaceProperties& properties() const { return properties_; }
    /** The object carrying `lm`, or nullptr for a fixed landmark. */
    const WorldObject* carrier(const Landmark& lm) const;

    /** True property of the surface `hit` (a ray cast on this world) at the global
     *  point `p` where the ray met it. */
    double propertyAt(const WorldSnapshot::Hit& hit, const Vec2& p) const;

private:
    std::vector<Landmark> landmarks_;
    std::vector<WorldObject> objects_;
    SurfaceProperties properties_;
};

}  // namespace hymm::sim
