/**
 * @file LayerOutputs.h
 * @brief What a run does with the content of one dense layer kind: its files, its counters
 *        in metrics.json, the map points its outline metrics score and its line in
 *        summary.txt. Each kind declares these hooks beside its layer
 *        (`src/<Layer>Outputs.cpp`) and its row in the layer table (LayerRegistry.h)
 *        carries them; hymm-slam's outputs iterate over the table.
 */
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <iosfwd>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace hymm::ltr
{
class RegionPartition;
}

namespace hymm::dense
{
class HybridMetricMap;

constexpr double kPointsPngResolution = 0.1;  //!< [m/pixel] of the point images
/** Cells (and particles) above this P(occupied) are the occupied content the outline
 *  metrics score (the P > 0.8 of the thesis' occupancy figures, Fig. 4.3). */
constexpr double kOccupiedProbability = 0.8;

/** What the hooks see of a run. */
struct LayerOutputContext
{
    const HybridMetricMap& map;
    const ltr::RegionPartition& partition;
    /** Returns the run stored in regions (a layer says why it is empty when it is). */
    size_t returns_stored = 0;
};

/** One counter of metrics.json "dense" / <kind>: a count, a real or a text. */
using LayerCounter = std::pair<std::string, std::variant<unsigned long, double, std::string>>;

/** The hooks of one kind. */
struct LayerOutputs
{
    /** Writes the kind's files into the folder `dir` ('/'-terminated); images when `png`. */
    void (*write)(const LayerOutputContext& c, const std::string& dir, bool png) = nullptr;
    /** Counters beyond items and memory_bytes (none when null). */
    std::vector<LayerCounter> (*counts)(const LayerOutputContext& c) = nullptr;
    /** The map points the outline metrics score (occupied content of the rendered map). */
    std::vector<Eigen::Vector2d> (*scored_points)(const LayerOutputContext& c) = nullptr;
    /** summary.txt: what the kind holds, `n` = DenseLayer::size() summed over regions. */
    void (*describe)(std::ostream& f, const LayerOutputContext& c, size_t n) = nullptr;
};

}  // namespace hymm::dense
