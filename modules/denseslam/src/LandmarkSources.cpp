// The registries of landmark sources (LandmarkSources.h).
#include "hymm/denseslam/LandmarkSources.h"

#include "PointSources.h"

namespace hymm::denseslam
{
namespace
{
/** Options of `section` from `cfg` (defaults when null). */
template <class O>
O sectionOptions(const mrpt::config::CConfigFileBase* cfg, const char* section)
{
    O o;
    if (cfg) o.loadFromConfigFile(*cfg, section);
    return o;
}
}  // namespace

const std::vector<PointSourceKind>& pointSourceKinds()
{
    // Scan sources in the order their features of one scan are fused: a beacon's
    // reflector before the tree seen on the same pole or trunk (the reflector's intensity
    // marks the beacon the map is built on).
    static const std::vector<PointSourceKind> kinds = {
        {"bearing_range", "[DenseSlam] (noise overrides, ranges, use_landmark_ids)",
         PointSourceInput::BearingRange,
         [](const mrpt::config::CConfigFileBase*, const PointSourceSettings& s) -> std::unique_ptr<PointLandmarkSource> {
             return std::make_unique<BearingRangeSource>(s);
         }},
        {"laser_reflectors", "[ReflectorExtractor]", PointSourceInput::Scan,
         [](const mrpt::config::CConfigFileBase* cfg, const PointSourceSettings& s) -> std::unique_ptr<PointLandmarkSource> {
             return std::make_unique<ReflectorSource>(
                 "laser_reflectors", sectionOptions<extract::ReflectorExtractor::Options>(cfg, "ReflectorExtractor"), s);
         }},
        {"laser_trees", "[TreeExtractor]", PointSourceInput::Scan,
         [](const mrpt::config::CConfigFileBase* cfg, const PointSourceSettings& s) -> std::unique_ptr<PointLandmarkSource> {
             return std::make_unique<TreeSource>("laser_trees",
                                                 sectionOptions<extract::TreeExtractor::Options>(cfg, "TreeExtractor"), s);
         }},
    };
    return kinds;
}

const PointSourceKind* findPointSourceKind(const std::string& name)
{
    for (const auto& k : pointSourceKinds())
        if (k.name == name) return &k;
    return nullptr;
}

const std::vector<std::pair<std::string, std::vector<std::string>>>& pointSourceAliases()
{
    static const std::vector<std::pair<std::string, std::vector<std::string>>> aliases = {
        {"both", {"bearing_range", "laser_trees"}},
        {"laser_reflectors_and_trees", {"laser_reflectors", "laser_trees"}},
    };
    return aliases;
}

const std::vector<LandmarkSourceKind>& landmarkSourceKinds()
{
    static const std::vector<LandmarkSourceKind> kinds = {
        {"scan_landmarks",
         "[ScanLandmarks], [ScanSegmentation], [ScanAcceptance], [SogMatcher] / [IcpMatcher] / "
         "[CorrelativeMatcher]",
         [](const mrpt::config::CConfigFileBase* cfg) -> std::unique_ptr<ScanLandmarkSource> {
             return std::make_unique<ScanLandmarksSource>(scanslam::ScanLandmarkMap::fromConfig(cfg));
         }},
    };
    return kinds;
}

const LandmarkSourceKind* findLandmarkSourceKind(const std::string& name)
{
    for (const auto& k : landmarkSourceKinds())
        if (k.name == name) return &k;
    return nullptr;
}

}  // namespace hymm::denseslam
