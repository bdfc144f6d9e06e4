/**
 * @file ParticlesLayerOutputs.cpp
 * @brief The particles layer's outputs: particles.bin (MRPT CPointsMapXYZI, the weight
 *        P(occupied) as intensity), particles.txt and particles.png; its outline metrics
 *        score the particles above kParticleOccupiedWeight.
 */
#include "layer_outputs.h"

#include "hymm/core/output_files.h"
#include "hymm/core/serialized_file.h"
#include "hymm/dense/HybridMetricMap.h"
#include "hymm/dense/ParticlesLayer.h"
#include "hymm/dense/map_images.h"

#include <mrpt/maps/CPointsMapXYZI.h>

#include <cmath>
#include <iomanip>
#include <ostream>

namespace hymm::dense
{
namespace
{
/** Particles with a weight above this are the occupied content (the P > 0.8 of the
 *  occupancy maps, Fig. 4.3); the thesis (Sec. 4.2.3) reports the fractions of weights
 *  above it and below kParticleLowWeight (the metrics' names carry both values). */
constexpr double kParticleOccupiedWeight = 0.8;
constexpr double kParticleLowWeight = 0.5;

// Every particle at its current position, the weight P(occupied) as intensity.
mrpt::maps::CPointsMapXYZI renderParticles(const LayerOutputContext& c)
{
    mrpt::maps::CPointsMapXYZI pts;
    c.map.renderLayer(ParticlesLayer::kKind, c.partition, pts);
    return pts;
}

struct ParticleWeights
{
    size_t count = 0, above = 0, below = 0;  // w > kParticleOccupiedWeight, w < kParticleLowWeight
    std::vector<Eigen::Vector2d> occupied;   // positions of the `above` particles
    double fraction(size_t n) const
    {
        return count ? static_cast<double>(n) / count : std::nan("");
    }
};

ParticleWeights particleWeights(const mrpt::maps::CPointsMapXYZI& pts)
{
    ParticleWeights w;
    w.count = pts.size();
    for (size_t i = 0; i < pts.size(); ++i)
    {
        const double v = pts.getPointIntensity(i);
        if (v < kParticleLowWeight) ++w.below;
        if (v > kParticleOccupiedWeight)
        {
            ++w.above;
            w.occupied.emplace_back(pts.getPointsBufferRef_x()[i], pts.getPointsBufferRef_y()[i]);
        }
    }
    return w;
}

void writeParticles(const LayerOutputContext& c, const std::string& d, bool png)
{
    const auto pts = renderParticles(c);
    core::writeSerializedGz(pts, d + "particles.bin");
    core::AtomicTextFile f(d + "particles.txt");
    f << "# x y weight (P(occupied), thesis Eq. 4.9)\n" << std::setprecision(9);
    for (size_t i = 0; i < pts.size(); ++i)
        f << pts.getPointsBufferRef_x()[i] << ' ' << pts.getPointsBufferRef_y()[i] << ' '
          << pts.getPointIntensity(i) << '\n';
    f.commit();
    if (png)
        savePointsByValuePng(pts, d + "particles.png", kPointsPngResolution, 0.0, 1.0, &c.partition);
}

std::vector<LayerCounter> particleCounts(const LayerOutputContext& c)
{
    const ParticleWeights w = particleWeights(renderParticles(c));
    return {{"particles", static_cast<unsigned long>(w.count)},
            {"occupied_min_weight", kParticleOccupiedWeight},
            {"weight_fraction_above_0_8", w.fraction(w.above)},
            {"weight_fraction_below_0_5", w.fraction(w.below)}};
}

std::vector<Eigen::Vector2d> particlesScored(const LayerOutputContext& c)
{
    return particleWeights(renderParticles(c)).occupied;
}

void describeParticles(std::ostream& f, const LayerOutputContext& c, size_t n)
{
    const ParticleWeights w = particleWeights(renderParticles(c));
    f << n << " particles (w > 0.8: " << 100 * w.fraction(w.above)
      << "%, w < 0.5: " << 100 * w.fraction(w.below) << "%)";
}
}  // namespace

LayerOutputs particlesLayerOutputs()
{
    return {writeParticles, particleCounts, particlesScored, describeParticles};
}

}  // namespace hymm::dense
