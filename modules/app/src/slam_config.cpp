#include "hymm/app/slam_config.h"

#include <hymm/datasets/CarParkImporter.h>
#include <hymm/datasets/MrclamImporter.h>
#include <hymm/datasets/NoiseCalibration.h>
#include <hymm/datasets/VictoriaParkImporter.h>
#include <hymm/eval/LandmarkEvaluator.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <hymm/extract/ReflectorExtractor.h>
#include <hymm/extract/TreeExtractor.h>
#include <hymm/scanslam/CorrelativeMatcher.h>
#include <hymm/scanslam/IcpMatcher.h>
#include <hymm/scanslam/ScanOdometry.h>
#include <hymm/dense/LayerRegistry.h>
#include <hymm/scanslam/ScanLandmarkMap.h>
#include <hymm/scanslam/SegmentAcceptance.h>
#include <hymm/scanslam/Segmenter.h>
#include <hymm/scanslam/SogMatcher.h>
#include <hymm/sim/Scenario.h>

#include <algorithm>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace hymm::app
{
namespace
{
template <class O>
OptionSection declared(const char* module, const char* section)
{
    return {module, section, [](std::shared_ptr<void>& hold) {
                auto o = std::make_shared<O>();
                hold = o;
                return o->table();
            }};
}

std::string beginMarker(const OptionSection& s)
{
    return "<!-- options [" + s.section + "] begin: generated from the declarations by hymm-options-doc -->";
}
std::string endMarker(const OptionSection& s) { return "<!-- options [" + s.section + "] end -->"; }
}  // namespace

denseslam::DenseSlam loadSlamConfig(const core::StrictConfigFile& file)
{
    std::unique_ptr<denseslam::DenseSlam> slam;
    file.load([&](const mrpt::config::CConfigFileBase& cfg) {
        slam = std::make_unique<denseslam::DenseSlam>(denseslam::DenseSlam::fromConfig(cfg));
    });
    file.checkAllSectionsKnown();
    return std::move(*slam);
}

denseslam::DenseSlam loadSlamConfig(const std::string& path)
{
    return loadSlamConfig(core::StrictConfigFile(path));
}

namespace
{
// The dense layer kinds' sections, from the layer table (dense/LayerRegistry.h).
std::vector<OptionSection> layerSections()
{
    std::vector<OptionSection> out;
    for (const dense::LayerKind& k : dense::layerKinds())
        out.push_back({"dense", k.section, [&k](std::shared_ptr<void>& hold) {
                           auto o = std::make_shared<dense::HybridMetricMap::Options>();
                           hold = o;
                           return k.table(*o);
                       }});
    return out;
}

std::vector<OptionSection> declaredSections()
{
    using namespace hymm;
    std::vector<OptionSection> all = {
        declared<denseslam::DenseSlam::Options>("denseslam", "DenseSlam"),
        declared<denseslam::DenseSlam::LaserOptions>("denseslam", "Laser"),
        declared<ekf::EkfSlam::Options>("ekf", "EkfSlam"),
        declared<extract::TreeExtractor::Options>("extract", "TreeExtractor"),
        declared<extract::ReflectorExtractor::Options>("extract", "ReflectorExtractor"),
        declared<ltr::RegionPartition::Options>("ltr", "LtrPartition"),
        declared<ltr::VirtualLandmarkOptions>("ltr", "VirtualLandmarks"),
        declared<uif::DelayedDenseStore::Options>("uif", "DelayedDenseStore"),
        declared<dense::HybridMetricMap::Options>("dense", "HybridMetricMap"),
        declared<dense::ClassicOccupancyGrid::Options>("dense", "ClassicOccupancyGrid"),
        declared<dynamic::SlamMotionHook::Options>("dynamic", "DynamicSlam"),
        declared<dynamic::MotionDetector::Options>("dynamic", "MotionDetector"),
        declared<scanslam::ScanLandmarkMap::Options>("scanslam", "ScanLandmarks"),
        declared<scanslam::Segmenter::Options>("scanslam", "ScanSegmentation"),
        declared<scanslam::SegmentAcceptance::Options>("scanslam", "ScanAcceptance"),
        declared<scanslam::SogMatcher::Options>("scanslam", "SogMatcher"),
        declared<scanslam::IcpMatcher::Options>("scanslam", "IcpMatcher"),
        declared<scanslam::CorrelativeMatcher::Options>("scanslam", "CorrelativeMatcher"),
        declared<scanslam::ScanOdometry::Options>("scanslam", "ScanOdometry"),
        declared<eval::TrajectoryEvaluator::Options>("eval", "TrajectoryEvaluator"),
        declared<eval::LandmarkEvaluator::Options>("eval", "LandmarkEvaluator"),
        declared<datasets::VictoriaParkImporter::Options>("datasets", "VictoriaParkImporter"),
        declared<datasets::CarParkImporter::Options>("datasets", "CarParkImporter"),
        declared<datasets::MrclamImporter::Options>("datasets", "MrclamImporter"),
        declared<datasets::NoiseCalibrationOptions>("datasets", "NoiseCalibration"),
        declared<hll::HighLevelLandmarks::Options>("hll", "HighLevelLandmarks"),
        declared<sim::Scenario::Options>("sim", "Scenario"),
        declared<sim::Vehicle::Options>("sim", "Vehicle"),
        declared<sim::PathFollower::Options>("sim", "PathFollower"),
        declared<sim::World::Options>("sim", "World"),
        declared<sim::LaserSimulator::Options>("sim", "LaserSimulator"),
        declared<sim::LandmarkDetector::Options>("sim", "LandmarkDetector"),
        declared<sim::WorldPlot::Options>("sim", "WorldPlot"),
    };
    const auto layers = layerSections();
    const auto hybrid = std::find_if(all.begin(), all.end(),
                                     [](const OptionSection& o) { return o.section == "HybridMetricMap"; });
    all.insert(hybrid + 1, layers.begin(), layers.end());
    return all;
}
}  // namespace

const std::vector<OptionSection>& optionSections()
{
    static const std::vector<OptionSection> all = declaredSections();
    return all;
}

std::string readmeBlock(const OptionSection& s)
{
    std::shared_ptr<void> hold;
    return beginMarker(s) + "\n\n" + s.table(hold).markdown() + "\n" + endMarker(s) + "\n";
}

std::vector<std::string> syncReadmeTables(const std::string& root, bool write)
{
    std::vector<std::string> stale;
    for (const auto& s : optionSections())
    {
        const std::string path = root + "/modules/" + s.module + "/README.md";
        std::ifstream in(path);
        if (!in) throw std::runtime_error("cannot read '" + path + "'");
        std::stringstream ss;
        ss << in.rdbuf();
        std::string text = ss.str();
        const std::string block = readmeBlock(s);
        const auto b = text.find(beginMarker(s));
        const auto e = b == std::string::npos ? b : text.find(endMarker(s), b);
        std::string updated;
        if (b == std::string::npos || e == std::string::npos)
            updated = text + "\n### `[" + s.section + "]` keys\n\n" + block;
        else
        {
            const auto e_end = text.find('\n', e);
            updated = text.substr(0, b) + block + (e_end == std::string::npos ? "" : text.substr(e_end + 1));
        }
        if (updated == text) continue;
        stale.push_back("[" + s.section + "] in " + path);
        if (write)
        {
            std::ofstream out(path, std::ios::trunc);
            out << updated;
            if (!out) throw std::runtime_error("cannot write '" + path + "'");
        }
    }
    return stale;
}

}  // namespace hymm::app
