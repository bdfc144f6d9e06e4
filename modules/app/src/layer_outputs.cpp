#include <hymm/dense/CHybridMetricMap.h>
#include "layer_outputs.h"
#include <hymm/core/output_files.h>
#include <cstdio>

#include <hymm/dense/map_images.h>
#include <mrpt/maps/CHeightGridMap2D.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPointPDFSOG.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <ostream>
#include <utility>

namespace hymm::app
{
namespace
{
/** Particles with a weight above this are the occupied content (the P > 0.8 of the
 *  occupancy maps, Fig. 4.3); the thesis (Sec. 4.2.3) reports the fractions of weights
 *  above it and below kParticleLowWeight. */
constexpr double kParticleOccupiedWeight = 0.8;
constexpr double kParticleLowWeight = 0.5;
constexpr double kSogSurfaceResolution = 0.1;    //!< [m/pixel] (thesis Fig. 4.12 b: 0.2 m)
constexpr double kSogEllipsesResolution = 0.05;  //!< [m/pixel]: 1-sigma ellipses are ~0.1 m
constexpr int kSogEllipsePoints = 24;            //!< vertices per ellipse

// ---- points ------------------------------------------------------------------------

mrpt::maps::CSimplePointsMap renderPoints(const DenseSlam& slam)
{
    mrpt::maps::CSimplePointsMap pts;
    slam.hybridMap()->renderPoints(*slam.partition(), pts);
    return pts;
}

// "x y" per line as CPointsMap::save2D_to_text_file writes it, with every write checked.
void writePointsText(const mrpt::maps::CSimplePointsMap& pts, const std::string& file)
{
    std::string text;
    char line[96];
    const auto& xs = pts.getPointsBufferRef_x();
    const auto& ys = pts.getPointsBufferRef_y();
    for (size_t i = 0; i < xs.size(); ++i)
    {
        const int n = std::snprintf(line, sizeof(line), "%f %f\n", static_cast<double>(xs[i]),
                                    static_cast<double>(ys[i]));
        text.append(line, static_cast<size_t>(std::max(n, 0)));
    }
    core::writeFileAtomically(file, text);
}

void writePoints(const DenseSlam& slam, const std::string& d, bool png)
{
    const auto pts = renderPoints(slam);
    writeSerialized(pts, d + "points.bin");
    writePointsText(pts, d + "points.txt");
    if (png) dense::savePointsPng(pts, d + "points.png", kPointsPngResolution, slam.partition());
}

std::vector<Eigen::Vector2d> pointsScored(const DenseSlam& slam)
{
    return dense::pointsOf(renderPoints(slam));
}

void describePoints(std::ostream& f, const DenseSlam&, size_t n) { f << n << " points"; }

// ---- occupancy ---------------------------------------------------------------------

// Occupancy layer rendered at its own cell size.
mrpt::maps::COccupancyGridMap2D renderOccupancy(const DenseSlam& slam)
{
    mrpt::maps::COccupancyGridMap2D grid;
    slam.hybridMap()->renderOccupancy(*slam.partition(),
                                      slam.hybridMap()->options().occupancy.cell_size_m, grid);
    return grid;
}

void writeOccupancyRegions(const DenseSlam& slam, const std::string& file)
{
    core::AtomicTextFile f(file);
    f << "id,coarse,cell_size_m,cells,occupied,free,memory_bytes\n";
    for (const auto& r : slam.hybridMap()->occupancyRegionStats(kOccupiedProbability))
        f << r.id << ',' << (r.coarse ? 1 : 0) << ',' << r.cell_size_m << ',' << r.cells << ','
          << r.occupied << ',' << r.free << ',' << r.memory_bytes << '\n';
    f.commit();
}

void writeOccupancy(const DenseSlam& slam, const std::string& d, bool png)
{
    const auto grid = renderOccupancy(slam);
    // MRPT reads a cell as P(free): the file holds 1 - P(occupied), as its tools expect.
    writeSerialized(dense::freeProbabilityGrid(grid), d + "occupancy.gridmap");
    if (png) dense::saveOccupancyPng(grid, d + "occupancy.png", slam.partition());
    writeOccupancyRegions(slam, d + "occupancy_regions.csv");
}

/** Number of occupancy regions at the coarse and at the fine cell size. Their content
 *  is compared on occupancy_regions.csv of runs with and without coarsening
 *  (benchmarks/dense_layers): a coarse cell is occupied when any fine cell it replaced
 *  was, so occupied fractions in the current cells are not comparable across sizes. */
struct CoarsenSummary
{
    size_t coarse = 0, fine = 0;
};

CoarsenSummary coarsenSummary(const DenseSlam& slam)
{
    CoarsenSummary c;
    for (const auto& r : slam.hybridMap()->occupancyRegionStats(kOccupiedProbability))
        (r.coarse ? c.coarse : c.fine) += 1;
    return c;
}

void occupancyCounts(eval::MetricsJson& oj, const DenseSlam& slam)
{
    const CoarsenSummary c = coarsenSummary(slam);
    oj.set("regions_coarse", static_cast<unsigned long>(c.coarse));
    oj.set("regions_fine", static_cast<unsigned long>(c.fine));
}

std::vector<Eigen::Vector2d> occupancyScored(const DenseSlam& slam)
{
    return dense::occupiedCellCentres(renderOccupancy(slam), kOccupiedProbability);
}

void describeOccupancy(std::ostream& f, const DenseSlam& slam, size_t n)
{
    const CoarsenSummary c = coarsenSummary(slam);
    f << n << " cells updated, regions coarse " << c.coarse << " / fine " << c.fine;
}

// ---- particles ---------------------------------------------------------------------

// Every particle at its current position, the weight P(occupied) as intensity.
mrpt::maps::CPointsMapXYZI renderParticles(const DenseSlam& slam)
{
    mrpt::maps::CPointsMapXYZI pts;
    slam.hybridMap()->renderLayer(dense::ParticlesLayer::kKind, *slam.partition(), pts);
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

void writeParticles(const DenseSlam& slam, const std::string& d, bool png)
{
    const auto pts = renderParticles(slam);
    writeSerialized(pts, d + "particles.bin");
    core::AtomicTextFile f(d + "particles.txt");
    f << "# x y weight (P(occupied), thesis Eq. 4.9)\n" << std::setprecision(9);
    for (size_t i = 0; i < pts.size(); ++i)
        f << pts.getPointsBufferRef_x()[i] << ' ' << pts.getPointsBufferRef_y()[i] << ' '
          << pts.getPointIntensity(i) << '\n';
    f.commit();
    if (png)
        dense::savePointsByValuePng(pts, d + "particles.png", kPointsPngResolution, 0.0, 1.0,
                                    slam.partition());
}

void particleCounts(eval::MetricsJson& pj, const DenseSlam& slam)
{
    const ParticleWeights w = particleWeights(renderParticles(slam));
    pj.set("particles", static_cast<unsigned long>(w.count));
    pj.set("occupied_min_weight", kParticleOccupiedWeight);
    pj.set("weight_fraction_above_0_8", w.fraction(w.above));
    pj.set("weight_fraction_below_0_5", w.fraction(w.below));
}

std::vector<Eigen::Vector2d> particlesScored(const DenseSlam& slam)
{
    return particleWeights(renderParticles(slam)).occupied;
}

void describeParticles(std::ostream& f, const DenseSlam& slam, size_t n)
{
    const ParticleWeights w = particleWeights(renderParticles(slam));
    f << n << " particles (w > 0.8: " << 100 * w.fraction(w.above)
      << "%, w < 0.5: " << 100 * w.fraction(w.below) << "%)";
}

// ---- sum of Gaussians --------------------------------------------------------------

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
            for (int c = 0; c < 2; ++c) m.val.cov(r, c) = g.cov(r, c);
        m.log_w = std::log(2 * M_PI) + 0.5 * std::log(g.cov.det());
        sog.push_back(m);
    }
    return sog;
}

// The SOG surface as drawn: overlapping peak-1 Gaussians sum far above 1 where a
// surface was seen on every lap (tens on landmark trunks), so the image shows
// log(1 + surface) with the colour scale up to the 99th percentile of the covered cells;
// single Gaussians (value 1) stay visible next to the heavily observed surfaces.
void saveSurfacePng(dense::ScalarField surface, const std::string& file)
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
    dense::saveScalarFieldPng(surface, file, 0.0, top);
}

void writeSog(const DenseSlam& slam, const std::string& d, bool png)
{
    const auto& partition = *slam.partition();
    writeSerialized(sogMixture(slam.hybridMap()->renderSogGaussians(partition)), d + "sog.bin");
    if (!png) return;
    dense::ScalarField surface;
    slam.hybridMap()->renderSogSurface(partition, kSogSurfaceResolution, surface);
    saveSurfacePng(std::move(surface), d + "sog_surface.png");
    dense::savePolylinesPng(slam.hybridMap()->renderSogEllipses(partition, kSogEllipsePoints),
                            d + "sog_ellipses.png", kSogEllipsesResolution, &partition);
}

void sogCounts(eval::MetricsJson& sj, const DenseSlam& slam)
{
    sj.set("gaussians", static_cast<unsigned long>(
                            slam.hybridMap()->renderSogGaussians(*slam.partition()).size()));
}

std::vector<Eigen::Vector2d> sogScored(const DenseSlam& slam)
{
    std::vector<Eigen::Vector2d> means;
    for (const auto& g : slam.hybridMap()->renderSogGaussians(*slam.partition()))
        means.emplace_back(g.mean.x(), g.mean.y());
    return means;
}

void describeSog(std::ostream& f, const DenseSlam&, size_t n) { f << n << " Gaussians"; }

// ---- property ----------------------------------------------------------------------

// Property mean / std at the layer's cell size, as images and as MRPT height grids
// (h = mean or std, w = values fused; CHeightGridMap2D serialises h and w only, so the
// std gets a grid of its own).
struct PropertyMaps
{
    dense::ScalarField mean, stddev;
    mrpt::maps::CHeightGridMap2D grid_mean, grid_std;
    size_t cells_with_value = 0;
    std::vector<Eigen::Vector2d> centres;  // of the grid cells with a value
};

PropertyMaps renderProperty(const DenseSlam& slam)
{
    PropertyMaps p;
    const auto* hybrid = slam.hybridMap();
    const double res = hybrid->options().property.cell_size_m;
    hybrid->renderProperty(*slam.partition(), res, p.mean, p.stddev);
    const Eigen::Vector2d hi =
        p.mean.origin + res * Eigen::Vector2d(p.mean.sizeX(), p.mean.sizeY());
    p.grid_mean.setSize(p.mean.origin.x(), hi.x(), p.mean.origin.y(), hi.y(), res);
    hybrid->renderLayer(dense::PropertyLayer::kKind, *slam.partition(), p.grid_mean);
    p.grid_std = p.grid_mean;
    for (unsigned cy = 0; cy < p.grid_mean.getSizeY(); ++cy)
        for (unsigned cx = 0; cx < p.grid_mean.getSizeX(); ++cx)
        {
            const auto* c = p.grid_mean.cellByIndex(cx, cy);
            if (!c || c->w == 0) continue;
            ++p.cells_with_value;
            p.centres.emplace_back(p.grid_mean.idx2x(cx), p.grid_mean.idx2y(cy));
            auto* s = p.grid_std.cellByIndex(cx, cy);
            s->h = s->u = c->var;
        }
    return p;
}

// Colour range of a field's finite values ([0, 1] without any).
std::pair<double, double> valueRange(const dense::ScalarField& f)
{
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (Eigen::Index i = 0; i < f.values.size(); ++i)
        if (std::isfinite(f.values(i)))
            lo = std::min(lo, f.values(i)), hi = std::max(hi, f.values(i));
    if (!(lo <= hi)) return {0.0, 1.0};
    if (hi - lo < 1e-9) return {lo - 0.5, hi + 0.5};
    return {lo, hi};
}

void writeProperty(const DenseSlam& slam, const std::string& d, bool png)
{
    const PropertyMaps p = renderProperty(slam);
    writeSerialized(p.grid_mean, d + "property.gridmap");
    writeSerialized(p.grid_std, d + "property_std.gridmap");
    if (!png) return;
    const auto [m_lo, m_hi] = valueRange(p.mean);
    dense::saveScalarFieldPng(p.mean, d + "property_mean.png", m_lo, m_hi, slam.partition());
    const auto [s_lo, s_hi] = valueRange(p.stddev);
    dense::saveScalarFieldPng(p.stddev, d + "property_std.png", std::min(0.0, s_lo), s_hi,
                              slam.partition());
}

void propertyCounts(eval::MetricsJson& pj, const DenseSlam& slam)
{
    const size_t cells = valueOr0(slam.hybridMap()->sizeByKind(), dense::PropertyLayer::kKind);
    pj.set("cells", static_cast<unsigned long>(cells));
    pj.set("rendered_cells", static_cast<unsigned long>(renderProperty(slam).cells_with_value));
    if (cells == 0 && slam.stats().returns_stored > 0)
        pj.set("note", "empty: the laser scans carry no values (intensities) to map");
}

std::vector<Eigen::Vector2d> propertyScored(const DenseSlam& slam)
{
    return renderProperty(slam).centres;
}

void describeProperty(std::ostream& f, const DenseSlam& slam, size_t n)
{
    f << n << " cells with a value"
      << (n == 0 && slam.stats().returns_stored > 0 ? " (the scans carry no intensities)" : "");
}
}  // namespace

const std::vector<LayerOutput>& layerOutputs()
{
    static const std::vector<LayerOutput> table = {
        {dense::PointsLayer::kKind, writePoints, nullptr, pointsScored, describePoints},
        {dense::OccupancyLayer::kKind, writeOccupancy, occupancyCounts, occupancyScored,
         describeOccupancy},
        {dense::ParticlesLayer::kKind, writeParticles, particleCounts, particlesScored,
         describeParticles},
        {dense::SogLayer::kKind, writeSog, sogCounts, sogScored, describeSog},
        {dense::PropertyLayer::kKind, writeProperty, propertyCounts, propertyScored,
         describeProperty},
    };
    return table;
}

const LayerOutput* findLayerOutput(const std::string& kind)
{
    for (const auto& l : layerOutputs())
        if (l.kind == kind) return &l;
    return nullptr;
}

std::vector<const LayerOutput*> enabledLayerOutputs(const DenseSlam& slam)
{
    std::vector<const LayerOutput*> out;
    if (!slam.hybridMap()) return out;
    for (const std::string& kind : slam.hybridMap()->enabledKinds())
        if (const auto* l = findLayerOutput(kind)) out.push_back(l);
    return out;
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
