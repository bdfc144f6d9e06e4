/**
 * @file layer_outputs.h
 * @brief What hymm-slam does with each kind of dense layer, in one table: its files, its
 *        counters in metrics.json, the map points its outline metrics score and its line
 *        in summary.txt. writeDenseOutputs, writeDenseMetrics and writeSummary iterate
 *        over the table; a new layer kind adds one entry (layer_outputs.cpp).
 */
#pragma once

#include <hymm/app/slam_outputs.h>
#include <hymm/eval/MetricsJson.h>
#include <hymm/core/output_files.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <Eigen/Core>

#include <iosfwd>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace hymm::app
{
constexpr double kPointsPngResolution = 0.1;  //!< [m/pixel]
constexpr double kOccupiedProbability = 0.8;  //!< occupied cells for the outline metrics

/** One kind of dense layer (dense::DenseLayer kind name) as the app sees it. */
struct LayerOutput
{
    std::string kind;
    /** Writes the layer's files into the folder `d` ('/'-terminated); images when `png`. */
    void (*write)(const DenseSlam& slam, const std::string& d, bool png) = nullptr;
    /** Counters beyond items and memory_bytes, into metrics.json "dense" / kind (may be null). */
    void (*counts)(eval::MetricsJson& lj, const DenseSlam& slam) = nullptr;
    /** The map points the outline metrics score (occupied content of the rendered map). */
    std::vector<Eigen::Vector2d> (*scored_points)(const DenseSlam& slam) = nullptr;
    /** summary.txt: what the layer holds, `n` = DenseLayer::size() summed over regions. */
    void (*describe)(std::ostream& f, const DenseSlam& slam, size_t n) = nullptr;
};

/** Every layer kind, in the order of dense::HybridMetricMap::enabledKinds(). */
const std::vector<LayerOutput>& layerOutputs();

/** The entry of `kind`, nullptr for a kind without one. */
const LayerOutput* findLayerOutput(const std::string& kind);

/** The entries of the layers the run has on (none without a hybrid map). */
std::vector<const LayerOutput*> enabledLayerOutputs(const DenseSlam& slam);

size_t valueOr0(const std::map<std::string, size_t>& m, const std::string& key);

/** `obj` MRPT-serialised into a gzip file (level 1, as CFileGZOutputStream writes it), as
 *  MRPT's map tools read it; serialised in memory first so that every write is checked. */
template <class T>
void writeSerialized(const T& obj, const std::string& file)
{
    mrpt::io::CMemoryStream mem;
    mrpt::serialization::archiveFrom(mem) << obj;
    core::writeGzFileAtomically(
        file, std::string_view(static_cast<const char*>(mem.getRawBufferData()),
                               static_cast<size_t>(mem.getTotalBytesCount())));
}

/** Landmarks in the filter by the feature kinds their observations came from. */
struct LandmarksByFeature
{
    size_t reflector_only = 0, tree_only = 0, both = 0;
};
LandmarksByFeature landmarksByFeature(const DenseSlam& slam);

}  // namespace hymm::app
