/**
 * @file SogLayerOutputs.cpp
 * @brief The sum-of-Gaussians layer's outputs: sog.bin (MRPT CPointPDFSOG),
 *        sog_surface.png (thesis Fig. 4.12 b) and sog_ellipses.png; its outline metrics
 *        score the Gaussians' means.
 */
#include "layer_outputs.h"

#include "hymm/core/serialized_file.h"
#include "hymm/dense/HybridMetricMap.h"
#include "hymm/dense/map_images.h"

#include <mrpt/poses/CPointPDFSOG.h>

#include <algorithm>
#include <cmath>
#include <ostream>

namespace hymm::dense
{
namespace
{
constexpr double kSogSurfaceResolution = 0.1;    //!< [m/pixel] (thesis Fig. 4.12 b: 0.2 m)
constexpr double kSogEllipsesResolution = 0.05;  //!< [m/pixel]: 1-sigma ellipses are ~0.1 m
constexpr int kSogEllipsePoints = 24;            //!< vertices per ellipse

// The Gaussians as an MRPT mixture in the plane (z = 0, zero z variance). Each weight is
// 2 pi sqrt|P|, the scale that gives the Gaussian a peak of 1 (thesis Sec. 4.3.1), so
// CPointPDFSOG::evaluatePDF(p, true) is the surface of Fig. 4.12 b; the map is not a
// distribution (Sec. 4.3) and the weights are deliberately not normalised.
mrpt::poses::CPointPDFSOG sogMixture(const std::vector<mrpt::poses::CPoint2DPDFGaussian>& gs)
{
    mrpt::poses::CPointPDFSOG sog(0);
    for (const auto& g : gs)
    {
        mrpt::poses::CPointPDFSOG::TGaussianMode m;
        m.val.mean = mrpt::poses::CPoint3D(g.mean.x(), g.mean.y(), 0.0);
        m.val.cov.setZero();
        for (int r = 0; r < 2; ++r)
            for (int col = 0; col < 2; ++col) m.val.cov(r, col) = g.cov(r, col);
        m.log_w = std::log(2 * M_PI) + 0.5 * std::log(g.cov.det());
        sog.push_back(m);
    }
    return sog;
}

// The SOG surface as drawn: overlapping peak-1 Gaussians sum far above 1 where a
// surface was seen on every lap (tens on landmark trunks), so the image shows
// log(1 + surface) with the colour scale up to the 99th percentile of the covered cells;
// single Gaussians (value 1) stay visible next to the heavily observed surfaces.
void saveSurfacePng(ScalarField surface, const std::string& file)
{
    constexpr double kCovered = 0.05;  // cells below are background
    std::vector<double> covered;
    for (Eigen::Index i = 0; i < surface.values.size(); ++i)
    {
        double& v = surface.values(i);
        v = std::log1p(std::max(0.0, v));
        if (v > std::log1p(kCovered)) covered.push_back(v);
    }
    double top = std::log1p(1.0);
    if (!covered.empty())
    {
        const auto k = covered.begin() +
                       static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(covered.size() - 1));
        std::nth_element(covered.begin(), k, covered.end());
        top = std::max(top, *k);
    }
    saveScalarFieldPng(surface, file, 0.0, top);
}

void writeSog(const LayerOutputContext& c, const std::string& d, bool png)
{
    core::writeSerializedGz(sogMixture(c.map.renderSogGaussians(c.partition)), d + "sog.bin");
    if (!png) return;
    ScalarField surface;
    c.map.renderSogSurface(c.partition, kSogSurfaceResolution, surface);
    saveSurfacePng(std::move(surface), d + "sog_surface.png");
    savePolylinesPng(c.map.renderSogEllipses(c.partition, kSogEllipsePoints), d + "sog_ellipses.png",
                     kSogEllipsesResolution, &c.partition);
}

std::vector<LayerCounter> sogCounts(const LayerOutputContext& c)
{
    return {{"gaussians", static_cast<unsigned long>(c.map.renderSogGaussians(c.partition).size())}};
}

std::vector<Eigen::Vector2d> sogScored(const LayerOutputContext& c)
{
    std::vector<Eigen::Vector2d> means;
    for (const auto& g : c.map.renderSogGaussians(c.partition)) means.emplace_back(g.mean.x(), g.mean.y());
    return means;
}

void describeSog(std::ostream& f, const LayerOutputContext&, size_t n) { f << n << " Gaussians"; }
}  // namespace

LayerOutputs sogLayerOutputs() { return {writeSog, sogCounts, sogScored, describeSog}; }

}  // namespace hymm::dense
