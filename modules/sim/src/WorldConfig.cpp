// Loading and saving of World::Options and of the [Object_<name>] sections.
#include <hymm/core/config_utils.h>
#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "config_text.h"
#include "hymm/sim/World.h"

namespace hymm::sim
{
using hymm::core::throwConfigError;

namespace
{
const std::vector<std::string> kObjectKeys = {"kind",     "shape",       "size",
                                              "vertices", "pose",        "trajectory",
                                              "appear_s", "disappear_s", "property",
                                              "landmarks"};

std::string raw(const mrpt::config::CConfigFileBase& cfg, const std::string& sec,
                const std::string& key)
{
    return hymm::core::readString(cfg, sec, key, "");
}

/** An optional finite number (surface properties); nullopt when the key is absent. */
std::optional<double> optionalFinite(const mrpt::config::CConfigFileBase& cfg,
                                     const std::string& sec, const std::string& key)
{
    if (!cfg.keyExists(sec, key)) return std::nullopt;
    const double v = hymm::core::readDouble(cfg, sec, key, 0);
    if (!std::isfinite(v)) throwConfigError(sec, key, raw(cfg, sec, key), "must be finite");
    return v;
}

Polygon outlineFromConfig(const mrpt::config::CConfigFileBase& cfg, const std::string& sec)
{
    const std::string shape = hymm::core::readString(cfg, sec, "shape", "", true);
    Polygon outline;
    if (shape == "box")
    {
        if (cfg.keyExists(sec, "vertices"))
            throwConfigError(sec, "vertices", raw(cfg, sec, "vertices"),
                             "a box takes 'size', not 'vertices'");
        const auto sz = detail::readGroups(cfg, sec, "size", 2, 1, true);
        if (sz.size() != 2 || !(sz[0] > 0) || !(sz[1] > 0))
            throwConfigError(sec, "size", detail::formatNumbers(sz),
                             "expected two positive numbers: length width");
        const double l = sz[0] / 2, w = sz[1] / 2;
        outline = {{-l, -w}, {l, -w}, {l, w}, {-l, w}};
    }
    else if (shape == "polygon")
    {
        if (cfg.keyExists(sec, "size"))
            throwConfigError(sec, "size", raw(cfg, sec, "size"),
                             "a polygon takes 'vertices', not 'size'");
        const auto v = detail::readGroups(cfg, sec, "vertices", 2, 3, true);
        for (size_t i = 0; i < v.size(); i += 2) outline.emplace_back(v[i], v[i + 1]);
    }
    else
        throwConfigError(sec, "shape", shape, "expected 'box' or 'polygon'");
    const double area = signedArea(outline);
    if (std::abs(area) < 1e-9)
        throwConfigError(sec, "vertices", raw(cfg, sec, "vertices"), "the outline has no area");
    if (area < 0) std::reverse(outline.begin(), outline.end());
    return outline;
}

std::vector<PoseKey> trajectoryFromConfig(const mrpt::config::CConfigFileBase& cfg,
                                          const std::string& sec)
{
    if (cfg.keyExists(sec, "pose") && cfg.keyExists(sec, "trajectory"))
        throwConfigError(sec, "trajectory", raw(cfg, sec, "trajectory"),
                         "give either 'pose' or 'trajectory'");
    std::vector<PoseKey> keys;
    if (cfg.keyExists(sec, "trajectory"))
    {
        const auto v = detail::readGroups(cfg, sec, "trajectory", 4, 1, true);
        for (size_t i = 0; i < v.size(); i += 4)
        {
            if (!keys.empty() && !(v[i] > keys.back().t))
                throwConfigError(sec, "trajectory", detail::formatNumbers(v),
                                 "key times must increase strictly");
            keys.push_back(PoseKey{v[i], v[i + 1], v[i + 2], mrpt::DEG2RAD(v[i + 3])});
        }
        return keys;
    }
    const auto p = detail::readGroups(cfg, sec, "pose", 3, 1);
    if (!p.empty() && p.size() != 3)
        throwConfigError(sec, "pose", detail::formatNumbers(p), "expected x y yaw_deg");
    if (p.empty()) return {PoseKey{}};
    return {PoseKey{0, p[0], p[1], mrpt::DEG2RAD(p[2])}};
}
}  // namespace

WorldObject WorldObject::fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                    const std::string& sec, long id)
{
    hymm::core::checkKnownKeys(cfg, sec, kObjectKeys);
    WorldObject obj;
    obj.id = id;
    obj.name = sec.substr(std::string(World::kObjectSectionPrefix).size());
    obj.kind = hymm::core::readString(cfg, sec, "kind", obj.kind);
    obj.outline = outlineFromConfig(cfg, sec);
    obj.trajectory = trajectoryFromConfig(cfg, sec);
    obj.present_from = hymm::core::readDouble(cfg, sec, "appear_s", obj.present_from);
    obj.present_to = hymm::core::readDouble(cfg, sec, "disappear_s", obj.present_to);
    if (!(obj.present_to > obj.present_from))
        throwConfigError(sec, "disappear_s", raw(cfg, sec, "disappear_s"),
                         "must be later than appear_s");
    obj.property = optionalFinite(cfg, sec, "property");
    const auto lm = detail::readGroups(cfg, sec, "landmarks", 3, 1);
    for (size_t i = 0; i + 2 < lm.size(); i += 3)
    {
        if (!(lm[i + 2] > 0))
            throwConfigError(sec, "landmarks", detail::formatNumber(lm[i + 2]), "radius must be > 0");
        obj.landmarks.push_back(CarriedLandmark{Vec2(lm[i], lm[i + 1]), lm[i + 2]});
    }
    return obj;
}

void WorldObject::toConfig(mrpt::config::CConfigFileBase& cfg, const std::string& sec) const
{
    cfg.write(sec, "kind", kind);
    cfg.write(sec, "shape", std::string("polygon"));
    std::vector<double> v;
    for (const auto& p : outline) v.insert(v.end(), {p.x(), p.y()});
    detail::writeNumbers(cfg, sec, "vertices", v);
    v.clear();
    for (const auto& k : trajectory) v.insert(v.end(), {k.t, k.x, k.y, mrpt::RAD2DEG(k.phi)});
    if (moves())
        detail::writeNumbers(cfg, sec, "trajectory", v);
    else
        detail::writeNumbers(cfg, sec, "pose", {v[1], v[2], v[3]});
    if (!std::isinf(present_from)) detail::writeNumber(cfg, sec, "appear_s", present_from);
    if (!std::isinf(present_to)) detail::writeNumber(cfg, sec, "disappear_s", present_to);
    if (property) detail::writeNumber(cfg, sec, "property", *property);
    v.clear();
    for (const auto& c : landmarks) v.insert(v.end(), {c.offset.x(), c.offset.y(), c.radius});
    if (!v.empty()) detail::writeNumbers(cfg, sec, "landmarks", v);
}

hymm::core::OptionTable World::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.custom(detail::groupsKey(
        "landmarks", "m", 3, 0, 1e6, "explicit landmarks `x y radius ...` (ids 0, 1, ... in this order)",
        [this](const std::vector<double>& v, const std::string& s, const std::string& raw) {
            landmarks.clear();
            for (size_t i = 0; i < v.size(); i += 3)
            {
                if (!(v[i + 2] > 0)) throwConfigError(s, "landmarks", raw, "landmark radius must be > 0");
                landmarks.push_back(Landmark{static_cast<long>(i / 3), Vec2(v[i], v[i + 1]), v[i + 2]});
            }
        },
        [this]() {
            std::vector<double> v;
            for (const auto& l : landmarks) v.insert(v.end(), {l.position.x(), l.position.y(), l.radius});
            return v;
        }));
    const Range length = between(0, 1e5);
    t.real("landmark_spacing_m", landmark_spacing_m, "m", length, "along-path spacing of generated landmarks (0: none)");
    t.real("landmark_offset_min_m", landmark_offset_min_m, "m", length, "lateral distance of a generated landmark from the path, least");
    t.real("landmark_offset_max_m", landmark_offset_max_m, "m", length, "... and most");
    t.real("landmark_radius_min_m", landmark_radius_min_m, "m", above(0, 100), "generated trunk radius, least");
    t.real("landmark_radius_max_m", landmark_radius_max_m, "m", above(0, 100), "... and most");
    t.real("landmark_separation_m", landmark_separation_m, "m", length, "least distance between generated landmarks and from them to any object");
    t.real("object_spacing_m", object_spacing_m, "m", length, "along-path spacing of generated objects (0: none)");
    t.real("object_offset_min_m", object_offset_min_m, "m", length, "lateral distance of a generated object's centre from the path, least");
    t.real("object_offset_max_m", object_offset_max_m, "m", length, "... and most");
    t.real("object_size_min_m", object_size_min_m, "m", above(0, 1e4), "generated object diameter, least");
    t.real("object_size_max_m", object_size_max_m, "m", above(0, 1e4), "... and most");
    t.real("object_separation_m", object_separation_m, "m", length, "least gap between objects");
    t.real("clearance_m", clearance_m, "m", length, "least gap between generated items and the path");
    t.integer("seed", seed, "", 0, 0xFFFFFFFFLL, "seed of the generation (not of the noise)");
    t.custom(detail::groupsKey(
        "landmark_property", "", 1, 0, 1e12, "surface property of every landmark trunk (default: the field's value)",
        [this](const std::vector<double>& v, const std::string& s, const std::string& raw) {
            if (v.size() > 1) throwConfigError(s, "landmark_property", raw, "expected one number");
            landmark_property.reset();  // empty: unset, as a scenario that does not name it
            if (!v.empty()) landmark_property = v[0];
        },
        [this]() { return landmark_property ? std::vector<double>{*landmark_property} : std::vector<double>{}; }));
    t.custom(detail::groupsKey(
        "property_field", "", 3, 0, 1e12, "`v0 gx gy`: property v0 + gx x + gy y of surfaces without their own (default: 0)",
        [this](const std::vector<double>& v, const std::string& s, const std::string& raw) {
            if (v.size() > 3) throwConfigError(s, "property_field", raw, "expected three finite numbers: v0 gx gy");
            property_field.reset();  // empty: unset, as a scenario that does not name it
            if (!v.empty()) property_field = PropertyField{v[0], v[1], v[2]};
        },
        [this]() {
            if (!property_field) return std::vector<double>{};
            return std::vector<double>{property_field->v0, property_field->gx, property_field->gy};
        }));
    return t;
}

void World::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                        const std::string& s)
{
    landmarks.clear();
    landmark_property.reset();
    property_field.reset();
    table().load(cfg, s);
    const auto checkRange = [&](const char* lo_key, double lo, const char* hi_key, double hi)
    {
        if (hi < lo)
            throwConfigError(
                s, hi_key, detail::formatNumber(hi),
                std::string("must be >= ") + lo_key + " (" + detail::formatNumber(lo) + ")");
    };
    checkRange("landmark_offset_min_m", landmark_offset_min_m, "landmark_offset_max_m",
               landmark_offset_max_m);
    checkRange("landmark_radius_min_m", landmark_radius_min_m, "landmark_radius_max_m",
               landmark_radius_max_m);
    checkRange("object_offset_min_m", object_offset_min_m, "object_offset_max_m",
               object_offset_max_m);
    checkRange("object_size_min_m", object_size_min_m, "object_size_max_m", object_size_max_m);

    // Object sections, in name order so that ids do not depend on the file's layout.
    objects.clear();
    std::vector<std::string> sections;
    cfg.getAllSections(sections);
    std::sort(sections.begin(), sections.end());
    const std::string prefix = kObjectSectionPrefix;
    for (const auto& sec : sections)
        if (sec.rfind(prefix, 0) == 0)
            objects.push_back(WorldObject::fromConfig(cfg, sec, static_cast<long>(objects.size())));
}

void World::Options::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                      const std::string& s) const
{
    // The optional keys only when set: scenarios without them keep their saved text.
    std::vector<std::string> unset;
    if (landmarks.empty()) unset.push_back("landmarks");
    if (!landmark_property) unset.push_back("landmark_property");
    if (!property_field) unset.push_back("property_field");
    auto copy = *this;
    detail::saveTable(cfg, s, copy.table(), unset);
    for (const auto& obj : objects) obj.toConfig(cfg, kObjectSectionPrefix + obj.name);
}

}  // namespace hymm::sim
