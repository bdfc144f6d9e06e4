/**
 * @file LayerRegistry.cpp
 * @brief The table of dense layer kinds (LayerRegistry.h): one row per kind.
 */
#include "hymm/dense/LayerRegistry.h"

#include "layer_outputs.h"

namespace hymm::dense
{
namespace
{
using Options = HybridMetricMap::Options;
using Vertices = hymm::ltr::TriangleFrame::Vertices;

/** One row: `Layer` with its options in the member `member` of HybridMetricMap::Options
 *  (read from the section named like the class), its switch `flag` with its `doc`, the
 *  expression that builds a layer from the options `o` and the region's `reference`
 *  triangle, and its output hooks `outputs` (layer_outputs.h). */
#define HYMM_LAYER_KIND(Layer, member, flag, doc, make_expr, outputs)                                                        \
    LayerKind                                                                                                  \
    {                                                                                                          \
        Layer::kKind, #Layer, doc, &Options::flag,                                                                  \
            [](const Options& o, const Vertices& reference) -> std::unique_ptr<DenseLayer> {                   \
                (void)reference;                                                                               \
                return make_expr;                                                                              \
            },                                                                                                 \
            [](Options& o, const mrpt::config::CConfigFileBase& cfg) { o.member.loadFromConfigFile(cfg, #Layer); }, \
            [](const Options& o, mrpt::config::CConfigFileBase& cfg) { o.member.saveToConfigFile(cfg, #Layer); },   \
            [](const Options& o) { o.member.validate(#Layer); },                                               \
            [](Options& o) { return o.member.table(); }, outputs                                             \
    }
}  // namespace

const std::vector<LayerKind>& layerKinds()
{
    // The order is the order of the layers in a region and of the outputs.
    static const std::vector<LayerKind> kinds = {
        HYMM_LAYER_KIND(PointsLayer, points, enable_points, "keep raw returns (Sec. 3.9)",
                        std::make_unique<PointsLayer>(o.points, reference), pointsLayerOutputs()),
        HYMM_LAYER_KIND(OccupancyLayer, occupancy, enable_occupancy, "keep occupancy grids (Sec. 4.1)",
                        std::make_unique<OccupancyLayer>(o.occupancy, reference),
                        occupancyLayerOutputs()),
        HYMM_LAYER_KIND(ParticlesLayer, particles, enable_particles, "keep particle sets (Sec. 4.2)",
                        std::make_unique<ParticlesLayer>(o.particles, reference),
                        particlesLayerOutputs()),
        HYMM_LAYER_KIND(SogLayer, sog, enable_sog, "keep sums of Gaussians (Sec. 4.3)",
                        std::make_unique<SogLayer>(o.sog), sogLayerOutputs()),
        HYMM_LAYER_KIND(PropertyLayer, property, enable_property, "keep scalar property grids",
                        std::make_unique<PropertyLayer>(o.property, reference),
                        propertyLayerOutputs()),
    };
    return kinds;
}

const LayerKind* findLayerKind(const std::string& name)
{
    for (const LayerKind& k : layerKinds())
        if (name == k.name) return &k;
    return nullptr;
}

std::string layerKindNames()
{
    std::string out;
    for (const LayerKind& k : layerKinds()) out += (out.empty() ? "" : ", ") + std::string(k.name);
    return out;
}

}  // namespace hymm::dense
