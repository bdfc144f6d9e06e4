#include "output_helpers.h"

#include <variant>

namespace hymm::app
{
dense::LayerOutputContext layerOutputContext(const DenseSlam& slam)
{
    return {*slam.hybridMap(), *slam.partition(), slam.stats().returns_stored};
}

std::vector<const dense::LayerKind*> enabledLayerKinds(const DenseSlam& slam)
{
    std::vector<const dense::LayerKind*> out;
    if (!slam.hybridMap() || !slam.partition()) return out;
    for (const std::string& kind : slam.hybridMap()->enabledKinds())
        if (const auto* k = dense::findLayerKind(kind)) out.push_back(k);
    return out;
}

void setCounter(eval::MetricsJson& j, const dense::LayerCounter& counter)
{
    std::visit([&](const auto& value) { j.set(counter.first, value); }, counter.second);
}

size_t valueOr0(const std::map<std::string, size_t>& m, const std::string& key)
{
    const auto it = m.find(key);
    return it == m.end() ? 0 : it->second;
}

LandmarksByFeature landmarksByFeature(const DenseSlam& slam)
{
    LandmarksByFeature n;
    for (const auto& [id, lf] : slam.landmarkFeatures())
        ++(lf.count("laser_reflectors") > 0 ? (lf.count("laser_trees") > 0 ? n.both : n.reflector_only)
                                            : n.tree_only);
    return n;
}

}  // namespace hymm::app
