// The registry of per-scan landmark sources (LandmarkSources.h).
#include "hymm/denseslam/LandmarkSources.h"

namespace hymm::denseslam
{
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
