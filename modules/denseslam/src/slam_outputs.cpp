#include "hymm/denseslam/slam_outputs.h"

#include <hymm/core/trajectory_io.h>
#include <hymm/dense/map_images.h>
#include <hymm/eval/LandmarkEvaluator.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <hymm/eval/metrics_report.h>
#include <hymm/eval/nees.h>
#include <hymm/eval/se2_alignment.h>
#include <hymm/ltr/outside_causes.h>
#include "hymm/denseslam/VirtualLandmarkView.h"
#include <hymm/sim/ground_truth_io.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CHeightGridMap2D.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPointPDFSOG.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace hymm::denseslam
{
namespace
{
bool endsWith(const std::string& s, const std::string& suffix)
{
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::vector<core::StampedPose2D> estimatedPath(const DenseSlam& slam)
{
    std::vector<core::StampedPose2D> out;
    out.reserve(slam.path().size());
    for (const auto& s : slam.path()) out.push_back({s.t, s.pose[0], s.pose[1], s.pose[2]});
    return out;
}

template <class T>
void writeSerialized(const T& obj, const std::string& file)
{
    mrpt::io::CFileGZOutputStream f;
    if (!f.open(file)) throw std::runtime_error("cannot write '" + file + "'");
    mrpt::serialization::archiveFrom(f) << obj;
}

// The true surfaces the dense maps are scored against: object outlines and trunk circles
// (`surfaces`) for accuracy, the object outlines alone for coverage (trunks are landmarks,
// not dense content to cover). `*_est`: the same moved into the filter's frame by the
// inverse of the landmark-map alignment (empty when there is none).
struct TrueSurfaces
{
    std::vector<dense::Polygon> outlines, surfaces, outlines_est, surfaces_est;
};

void setOutlineMetrics(eval::MetricsJson& j, const std::vector<Eigen::Vector2d>& points,
                       const TrueSurfaces& truth)
{
    const dense::OutlineMetrics acc = dense::evaluateOutlines(points, truth.surfaces);
    const dense::OutlineMetrics cov = dense::evaluateOutlines(points, truth.outlines);
    j.set("points", static_cast<unsigned long>(acc.points));
    j.set("mean_distance_m", acc.mean_distance_m);
    j.set("p95_distance_m", acc.p95_distance_m);
    j.set("coverage", cov.coverage);
    j.set("outline_samples", static_cast<unsigned long>(cov.outline_samples));
    if (truth.surfaces_est.empty()) return;
    const dense::OutlineMetrics acc_a = dense::evaluateOutlines(points, truth.surfaces_est);
    const dense::OutlineMetrics cov_a = dense::evaluateOutlines(points, truth.outlines_est);
    auto& a = j.object("aligned");
    a.set("mean_distance_m", acc_a.mean_distance_m);
    a.set("p95_distance_m", acc_a.p95_distance_m);
    a.set("coverage", cov_a.coverage);
}

std::vector<dense::Polygon> transformed(const std::vector<dense::Polygon>& in, const eval::Se2Transform& t)
{
    std::vector<dense::Polygon> out = in;
    for (auto& poly : out)
        for (auto& p : poly) p = t.apply(p);
    return out;
}

// Every estimated landmark paired with the nearest true one within `gate`.
struct LandmarkPairs
{
    std::vector<Eigen::Vector2d> est, truth;
    std::vector<long> ids;  //!< filter ids of `est`
};
LandmarkPairs nearestPairs(const DenseSlam& slam, const std::vector<TrueTrunk>& truth, double gate)
{
    LandmarkPairs out;
    for (const auto& e : estimatedLandmarks(slam.ekf()))
    {
        const TrueTrunk* best = nullptr;
        double best_d = gate;
        for (const auto& t : truth)
            if (const double d = (t.centre - e.position).norm(); d <= best_d) best_d = d, best = &t;
        if (!best) continue;
        out.est.push_back(e.position);
        out.truth.push_back(best->centre);
        out.ids.push_back(e.id);
    }
    return out;
}

/** The filter's own 1-sigma of the rotation fitted onto the true landmarks: J P J^T with
 *  P the joint covariance of the paired estimates (their cross-covariances included,
 *  which dominate: the common rotation is what the landmarks share). NaN if undefined. */
double alignmentRotationStd(const DenseSlam& slam, const LandmarkPairs& pairs)
{
    const auto J = eval::alignSE2RotationJacobian(pairs.est, pairs.truth);
    if (!J) return std::numeric_limits<double>::quiet_NaN();
    const auto& ekf = slam.ekf();
    std::vector<size_t> offsets;
    offsets.reserve(pairs.ids.size());
    for (long id : pairs.ids) offsets.push_back(ekf.landmarkBlock(id).offset);
    double var = 0;
    for (size_t a = 0; a < offsets.size(); ++a)
        for (size_t b = 0; b < offsets.size(); ++b)
            var += J->segment<2>(2 * a) * ekf.cov().block<2, 2>(offsets[a], offsets[b]) *
                   J->segment<2>(2 * b).transpose();
    return var >= 0 ? std::sqrt(var) : std::numeric_limits<double>::quiet_NaN();
}

// Occupancy layer rendered at its own cell size.
void renderOccupancy(const DenseSlam& slam, mrpt::maps::COccupancyGridMap2D& grid)
{
    slam.hybridMap()->renderOccupancy(*slam.partition(),
                                      slam.hybridMap()->options().occupancy.cell_size_m, grid);
}

constexpr double kPointsPngResolution = 0.1;  //!< [m/pixel]
constexpr double kOccupiedProbability = 0.8;  //!< occupied cells for the outline metrics
constexpr double kAlignmentGate = 3.0;  //!< [m] estimated-true landmark pairs for the map alignment
/** Particles with a weight above this are the occupied content (the P > 0.8 of the
 *  occupancy maps, Fig. 4.3); the thesis (Sec. 4.2.3) reports the fractions of weights
 *  above it and below kParticleLowWeight. */
constexpr double kParticleOccupiedWeight = 0.8;
constexpr double kParticleLowWeight = 0.5;
constexpr double kSogSurfaceResolution = 0.1;    //!< [m/pixel] (thesis Fig. 4.12 b: 0.2 m)
constexpr double kSogEllipsesResolution = 0.05;  //!< [m/pixel]: 1-sigma ellipses are ~0.1 m
constexpr int kSogEllipsePoints = 24;            //!< vertices per ellipse

bool particlesOn(const DenseSlam& slam)
{
    return slam.hybridMap() && slam.hybridMap()->options().enable_particles;
}
bool sogOn(const DenseSlam& slam)
{
    return slam.hybridMap() && slam.hybridMap()->options().enable_sog;
}
bool propertyOn(const DenseSlam& slam)
{
    return slam.hybridMap() && slam.hybridMap()->options().enable_property;
}

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

void writeParticles(const DenseSlam& slam, const std::string& d, bool png)
{
    const auto pts = renderParticles(slam);
    writeSerialized(pts, d + "particles.bin");
    std::ofstream f(d + "particles.txt");
    if (!f) throw std::runtime_error("cannot write '" + d + "particles.txt'");
    f << "# x y weight (P(occupied), thesis Eq. 4.9)\n" << std::setprecision(9);
    for (size_t i = 0; i < pts.size(); ++i)
        f << pts.getPointsBufferRef_x()[i] << ' ' << pts.getPointsBufferRef_y()[i] << ' '
          << pts.getPointIntensity(i) << '\n';
    if (!f) throw std::runtime_error("error writing '" + d + "particles.txt'");
    if (png)
        dense::savePointsByValuePng(pts, d + "particles.png", kPointsPngResolution, 0.0, 1.0,
                                    slam.partition());
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

void writeOccupancyRegions(const DenseSlam& slam, const std::string& file)
{
    std::ofstream f(file);
    if (!f) throw std::runtime_error("cannot write '" + file + "'");
    f << "id,coarse,cell_size_m,cells,occupied,free,memory_bytes\n";
    for (const auto& r : slam.hybridMap()->occupancyRegionStats(kOccupiedProbability))
        f << r.id << ',' << (r.coarse ? 1 : 0) << ',' << r.cell_size_m << ',' << r.cells << ','
          << r.occupied << ',' << r.free << ',' << r.memory_bytes << '\n';
    if (!f) throw std::runtime_error("error writing '" + file + "'");
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

size_t valueOr0(const std::map<std::string, size_t>& m, const std::string& key)
{
    const auto it = m.find(key);
    return it == m.end() ? 0 : it->second;
}
}  // namespace

std::vector<dense::Polygon> loadObjectOutlines(const std::string& file)
{
    if (!mrpt::system::fileExists(file))
        throw std::runtime_error("ground-truth object file not found: '" + file + "'");
    std::vector<dense::Polygon> out;
    for (const auto& r : sim::readObjectOutlines(file))
        out.emplace_back(r.outline.begin(), r.outline.end());
    if (out.empty()) throw std::runtime_error("ground-truth object file '" + file + "' holds no outline");
    return out;
}

void writeDenseOutputs(const DenseSlam& slam, const std::string& dir, bool png)
{
    const std::string d = dir.empty() || dir.back() == '/' ? dir : dir + "/";
    const auto* partition = slam.partition();
    const auto* hybrid = slam.hybridMap();
    if (partition) partition->saveToFile(d + "regions.txt");
    if (hybrid && hybrid->options().enable_points)
    {
        mrpt::maps::CSimplePointsMap pts;
        hybrid->renderPoints(*partition, pts);
        writeSerialized(pts, d + "points.bin");
        if (!pts.save2D_to_text_file(d + "points.txt"))
            throw std::runtime_error("cannot write '" + d + "points.txt'");
        if (png) dense::savePointsPng(pts, d + "points.png", kPointsPngResolution, partition);
    }
    if (hybrid && hybrid->options().enable_occupancy)
    {
        mrpt::maps::COccupancyGridMap2D grid;
        renderOccupancy(slam, grid);
        writeSerialized(grid, d + "occupancy.gridmap");
        if (png) dense::saveOccupancyPng(grid, d + "occupancy.png", partition);
    }
    if (hybrid && hybrid->options().enable_occupancy)
        writeOccupancyRegions(slam, d + "occupancy_regions.csv");
    if (particlesOn(slam)) writeParticles(slam, d, png);
    if (sogOn(slam)) writeSog(slam, d, png);
    if (propertyOn(slam)) writeProperty(slam, d, png);
    if (const auto* classic = slam.classicGrid())
    {
        mrpt::maps::COccupancyGridMap2D grid;
        classic->toOccupancyGridMap(grid);
        writeSerialized(grid, d + "classic_grid.gridmap");
        if (png) dense::saveOccupancyPng(grid, d + "classic_grid.png");
    }
}

namespace
{
/** Why the returns in no region fell there (ltr/outside_causes.h), on the final map:
 *  all of them, and those the fallback did not keep. */
struct OutsideCauses
{
    ltr::OutsideCauseCounts all, dropped;
};
OutsideCauses outsideCauses(const DenseSlam& slam)
{
    OutsideCauses c;
    const VirtualLandmarkView view(slam.ekf(), slam.virtualLandmarkIds());
    for (const auto& r : slam.outsideReturns())
    {
        const auto cause = ltr::classifyOutsideReturn(*slam.partition(), view, r.p);
        ++c.all[cause];
        if (!r.kept) ++c.dropped[cause];
    }
    return c;
}

// Counts and memory of every layer (metrics.json "dense"; also without --gt-objects).
void writeLayerCounts(eval::MetricsJson& dj, const DenseSlam& slam)
{
    const auto* hybrid = slam.hybridMap();
    const auto items = hybrid->sizeByKind();
    const auto bytes = hybrid->memoryBytesByKind();
    auto& mj = dj.object("memory_bytes_by_kind");
    for (const std::string& kind : hybrid->enabledKinds())
    {
        mj.set(kind, static_cast<unsigned long>(valueOr0(bytes, kind)));
        auto& lj = dj.object(kind);
        lj.set("items", static_cast<unsigned long>(valueOr0(items, kind)));
        lj.set("memory_bytes", static_cast<unsigned long>(valueOr0(bytes, kind)));
    }
    if (hybrid->options().enable_occupancy)
    {
        const CoarsenSummary c = coarsenSummary(slam);
        auto& oj = dj.object("occupancy");
        oj.set("regions_coarse", static_cast<unsigned long>(c.coarse));
        oj.set("regions_fine", static_cast<unsigned long>(c.fine));
    }
    if (particlesOn(slam))
    {
        const ParticleWeights w = particleWeights(renderParticles(slam));
        auto& pj = dj.object("particles");
        pj.set("particles", static_cast<unsigned long>(w.count));
        pj.set("occupied_min_weight", kParticleOccupiedWeight);
        pj.set("weight_fraction_above_0_8", w.fraction(w.above));
        pj.set("weight_fraction_below_0_5", w.fraction(w.below));
    }
    if (sogOn(slam))
        dj.object("sog").set(
            "gaussians",
            static_cast<unsigned long>(hybrid->renderSogGaussians(*slam.partition()).size()));
    if (propertyOn(slam))
    {
        auto& pj = dj.object("property");
        const size_t cells = valueOr0(items, dense::PropertyLayer::kKind);
        pj.set("cells", static_cast<unsigned long>(cells));
        pj.set("rendered_cells", static_cast<unsigned long>(renderProperty(slam).cells_with_value));
        if (cells == 0 && slam.stats().returns_stored > 0)
            pj.set("note", "empty: the laser scans carry no values (intensities) to map");
    }
}

/** Landmarks in the filter by the feature kinds their observations came from. */
struct LandmarksByFeature
{
    size_t reflector_only = 0, tree_only = 0, both = 0;
};

LandmarksByFeature landmarksByFeature(const DenseSlam& slam)
{
    LandmarksByFeature n;
    for (const auto& [id, lf] : slam.landmarkFeatures())
        ++(lf.reflector > 0 ? (lf.tree > 0 ? n.both : n.reflector_only) : n.tree_only);
    return n;
}
}  // namespace

std::vector<TrueTrunk> trueTrunks(const std::vector<core::LandmarkRecord>& landmarks)
{
    std::vector<TrueTrunk> out;
    out.reserve(landmarks.size());
    for (const auto& l : landmarks)
        out.push_back({Eigen::Vector2d(l.x, l.y), l.extra.empty() ? 0.0 : l.extra[0]});
    return out;
}

void writeDenseMetrics(eval::MetricsJson& j, const DenseSlam& slam,
                       const std::vector<dense::Polygon>& outlines,
                       const std::vector<TrueTrunk>& true_landmarks)
{
    if (!slam.partition() && !slam.classicGrid()) return;
    auto& dj = j.object("dense");
    const auto& st = slam.stats();
    if (const auto* partition = slam.partition())
    {
        dj.set("regions", static_cast<unsigned long>(partition->size()));
        dj.set("regions_created", static_cast<unsigned long>(st.regions_created));
        dj.set("regions_removed", static_cast<unsigned long>(st.regions_removed));
        dj.set("virtual_landmarks", static_cast<unsigned long>(slam.virtualLandmarkIds().size()));
        dj.set("returns_stored", static_cast<unsigned long>(st.returns_stored));
        dj.set("returns_outside", static_cast<unsigned long>(st.returns_outside));
        dj.set("returns_withheld", static_cast<unsigned long>(st.returns_withheld));
        dj.set("returns_fallback", static_cast<unsigned long>(st.returns_fallback));
        dj.set("returns_dropped", static_cast<unsigned long>(st.returns_dropped));
        {
            // Where every return within range went: outside = fallback + delayed store + dropped.
            auto& rj = dj.object("returns");
            rj.set("total", static_cast<unsigned long>(st.returns_stored + st.returns_withheld + st.returns_outside));
            rj.set("stored_in_region", static_cast<unsigned long>(st.returns_stored));
            rj.set("withheld_local_uncertainty", static_cast<unsigned long>(st.returns_withheld));
            rj.set("withheld_kept_by_fallback", static_cast<unsigned long>(st.returns_withheld_fallback));
            rj.set("withheld_dropped", static_cast<unsigned long>(st.returns_withheld - st.returns_withheld_fallback));
            rj.set("outside_regions", static_cast<unsigned long>(st.returns_outside));
            rj.set("kept_by_fallback", static_cast<unsigned long>(st.returns_fallback));
            rj.set("delayed_stored", static_cast<unsigned long>(st.delayed_stored));
            rj.set("delayed_fused", static_cast<unsigned long>(st.delayed_fused));
            rj.set("dropped_outside", static_cast<unsigned long>(st.returns_dropped));
            // Returns within max_range_m that are in a dense layer (in a region, kept by the
            // fallback, or fused later from the delayed store).
            const size_t total = st.returns_stored + st.returns_withheld + st.returns_outside;
            const size_t reached = st.returns_stored + st.returns_fallback + st.returns_withheld_fallback + st.delayed_fused;
            rj.set("reached_dense_map", static_cast<unsigned long>(reached));
            rj.set("reached_fraction", total ? static_cast<double>(reached) / static_cast<double>(total) : 0.0);
            const auto causes = outsideCauses(slam);
            rj.set("outside_recorded", static_cast<unsigned long>(causes.all.total()));
            auto& cj = rj.object("outside_causes");
            auto& dcj = rj.object("dropped_causes");
            for (size_t k = 0; k < causes.all.n.size(); ++k)
            {
                const char* name = ltr::toString(static_cast<ltr::OutsideCause>(k));
                cj.set(name, static_cast<unsigned long>(causes.all.n[k]));
                dcj.set(name, static_cast<unsigned long>(causes.dropped.n[k]));
            }
        }
        dj.set("no_return_beams", static_cast<unsigned long>(st.no_return_beams));
        dj.set("failed_readings", static_cast<unsigned long>(st.failed_readings));
        if (slam.delayedStore())
        {
            auto& sj = dj.object("delayed_store");
            sj.set("stored", static_cast<unsigned long>(st.delayed_stored));
            sj.set("fused", static_cast<unsigned long>(st.delayed_fused));
            sj.set("waiting", static_cast<unsigned long>(slam.delayedStore()->numStoredPoints()));
            sj.set("outside_potential", static_cast<unsigned long>(st.delayed_outside_potential));
            sj.set("thinned", static_cast<unsigned long>(st.delayed_thinned));
            sj.set("evicted", static_cast<unsigned long>(st.delayed_evicted));
            sj.set("lost", static_cast<unsigned long>(st.delayed_lost));
        }
        dj.set("memory_bytes", static_cast<unsigned long>(slam.hybridMap()->memoryBytes()));
        writeLayerCounts(dj, slam);
    }
    if (outlines.empty()) return;
    TrueSurfaces truth;
    truth.outlines = outlines;
    truth.surfaces = outlines;
    for (const auto& t : true_landmarks) truth.surfaces.push_back(dense::circlePolygon(t.centre, t.radius));
    // The filter's frame is fixed by the start pose, but heading error gathered before the
    // first landmarks are mapped is never observable again: the whole map, landmarks and
    // dense content alike, carries a common rigid error. Scoring the maps also after the
    // least-squares SE(2) fit of the landmark map onto the true landmarks (one transform for
    // every map, the classic grid included, since all share the filter's frame) separates
    // that common part from the shape of each map.
    const LandmarkPairs pairs = nearestPairs(slam, true_landmarks, kAlignmentGate);
    if (const auto t = eval::alignSE2(pairs.est, pairs.truth); t && pairs.est.size() >= 3)
    {
        const eval::Se2Transform to_est = t->inverse();
        truth.outlines_est = transformed(truth.outlines, to_est);
        truth.surfaces_est = transformed(truth.surfaces, to_est);
        double before = 0, after = 0;
        for (size_t i = 0; i < pairs.est.size(); ++i)
        {
            before += (pairs.est[i] - pairs.truth[i]).norm();
            after += (t->apply(pairs.est[i]) - pairs.truth[i]).norm();
        }
        auto& aj = dj.object("landmark_alignment");
        aj.set("landmarks", static_cast<unsigned long>(pairs.est.size()));
        aj.set("x", t->x);
        aj.set("y", t->y);
        aj.set("phi_deg", t->phi * 180.0 / M_PI);
        // How unlikely the common rotation is by the filter's own account: |phi| / sigma is
        // ~N(0,1) over runs when the rotation is the information limit of the start, not
        // a defect (docs/results.md).
        const double phi_std = alignmentRotationStd(slam, pairs);
        if (std::isfinite(phi_std))
        {
            aj.set("phi_std_deg", phi_std * 180.0 / M_PI);
            if (phi_std > 0) aj.set("phi_normalised", t->phi / phi_std);
        }
        aj.set("landmark_mean_error_m", before / static_cast<double>(pairs.est.size()));
        aj.set("landmark_mean_error_aligned_m", after / static_cast<double>(pairs.est.size()));
    }
    const auto* hybrid = slam.hybridMap();
    if (hybrid && hybrid->options().enable_points)
    {
        mrpt::maps::CSimplePointsMap pts;
        hybrid->renderPoints(*slam.partition(), pts);
        setOutlineMetrics(dj.object("points"), dense::pointsOf(pts), truth);
    }
    if (hybrid && hybrid->options().enable_occupancy)
    {
        mrpt::maps::COccupancyGridMap2D grid;
        renderOccupancy(slam, grid);
        setOutlineMetrics(dj.object("occupancy"), dense::occupiedCellCentres(grid, kOccupiedProbability), truth);
    }
    if (hybrid && hybrid->fallbackTiles() > 0)
    {
        // The fallback's content alone: its error includes the extrapolated affine maps.
        auto& fj = dj.object("fallback");
        fj.set("tiles", static_cast<unsigned long>(hybrid->fallbackTiles()));
        if (hybrid->options().enable_points)
        {
            mrpt::maps::CSimplePointsMap pts;
            hybrid->renderPoints(*slam.partition(), pts, dense::HybridMetricMap::Content::Fallback);
            setOutlineMetrics(fj.object("points"), dense::pointsOf(pts), truth);
        }
        if (hybrid->options().enable_occupancy)
        {
            mrpt::maps::COccupancyGridMap2D grid;
            hybrid->renderOccupancy(*slam.partition(), hybrid->options().occupancy.cell_size_m, grid,
                                    dense::HybridMetricMap::Content::Fallback);
            setOutlineMetrics(fj.object("occupancy"), dense::occupiedCellCentres(grid, kOccupiedProbability), truth);
        }
    }
    if (particlesOn(slam))
        setOutlineMetrics(dj.object("particles"), particleWeights(renderParticles(slam)).occupied, truth);
    if (sogOn(slam))
    {
        std::vector<Eigen::Vector2d> means;
        for (const auto& g : hybrid->renderSogGaussians(*slam.partition()))
            means.emplace_back(g.mean.x(), g.mean.y());
        setOutlineMetrics(dj.object("sog"), means, truth);
    }
    if (propertyOn(slam))
        setOutlineMetrics(dj.object("property"), renderProperty(slam).centres, truth);
    if (const auto* classic = slam.classicGrid())
    {
        mrpt::maps::COccupancyGridMap2D grid;
        classic->toOccupancyGridMap(grid);
        setOutlineMetrics(dj.object("classic_grid"),
                          dense::occupiedCellCentres(grid, kOccupiedProbability), truth);
    }
}

std::vector<eval::LandmarkEstimate> estimatedLandmarks(const ekf::EkfSlam& ekf)
{
    std::vector<eval::LandmarkEstimate> out;
    for (long id : ekf.landmarkIds())
    {
        if (ekf.landmarkBlock(id).dim != 2) continue;
        eval::LandmarkEstimate e;
        e.id = id;
        e.position = ekf.landmarkMean(id);
        e.cov = ekf.landmarkCov(id);
        e.has_cov = true;
        out.push_back(e);
    }
    return out;
}
eval::LandmarkEvaluator::Association landmarkAssociationFor(const DenseSlam& slam)
{
    return slam.stats().observations_with_id > 0 ? eval::LandmarkEvaluator::Association::Id
                                                  : eval::LandmarkEvaluator::Association::Nearest;
}

std::vector<double> vehicleNeesSeries(const DenseSlam& slam, const GroundTruth& gt,
                                      double time_tolerance)
{
    const auto& path = slam.path();
    std::vector<double> out(path.size(), std::nan(""));
    if (gt.path.empty()) return out;
    eval::TrajectoryEvaluator::Options to;
    to.association = gt.path_has_timestamps ? eval::TrajectoryEvaluator::Association::Nearest
                                            : eval::TrajectoryEvaluator::Association::Index;
    to.time_tolerance = time_tolerance;
    const auto traj = eval::TrajectoryEvaluator(to).evaluate(estimatedPath(slam), gt.path);
    // Errors come in the order of the estimates; walk both sequences together.
    size_t i = 0;
    for (const auto& e : traj.errors)
    {
        while (i < path.size() && path[i].t != e.t) ++i;
        if (i == path.size()) break;
        const auto v = eval::nees(Eigen::Vector3d(e.dx, e.dy, e.dphi), path[i].cov);
        if (v.ok()) out[i] = v.value;
        ++i;
    }
    return out;
}

GroundTruth loadGroundTruth(const std::string& path_file, const std::string& landmarks_file)
{
    GroundTruth gt;
    if (!path_file.empty())
    {
        if (!mrpt::system::fileExists(path_file))
            throw std::runtime_error("ground-truth path file not found: '" + path_file + "'");
        if (endsWith(path_file, "_ground_truth_robot_path.txt"))
        {
            gt.path = eval::readSimulLandmarksPath(path_file);
            gt.path_has_timestamps = false;
        }
        else
        {
            gt.path = core::readTum(path_file);
        }
    }
    if (!landmarks_file.empty())
    {
        if (!mrpt::system::fileExists(landmarks_file))
            throw std::runtime_error("ground-truth landmark file not found: '" + landmarks_file + "'");
        gt.landmarks = endsWith(landmarks_file, "_ground_truth.txt")
                           ? eval::readSimulLandmarksLandmarks(landmarks_file)
                           : core::readLandmarksCsv(landmarks_file);
    }
    return gt;
}

void writeEstimatedPath(const DenseSlam& slam, const std::string& file)
{
    core::writeTum(file, estimatedPath(slam));
}

void writeEstimatedLandmarks(const ekf::EkfSlam& ekf, const std::string& file)
{
    std::vector<core::LandmarkRecord> recs;
    for (const auto& e : estimatedLandmarks(ekf))
        recs.push_back({e.id, e.position.x(), e.position.y(), {e.cov(0, 0), e.cov(0, 1), e.cov(1, 1)}});
    core::writeLandmarksCsv(file, recs, "id,x,y,cxx,cxy,cyy");
}

MapPlot makeMapPlot(const DenseSlam& slam, const GroundTruth* gt)
{
    MapPlot p;
    for (const auto& s : slam.path()) p.estimated_path.emplace_back(s.pose[0], s.pose[1]);
    for (const auto& e : estimatedLandmarks(slam.ekf())) p.estimated_landmarks.push_back({e.position, e.cov});
    if (const auto* hybrid = slam.hybridMap(); hybrid && hybrid->options().enable_points)
    {
        mrpt::maps::CSimplePointsMap pts;
        hybrid->renderPoints(*slam.partition(), pts);
        p.dense_points = dense::pointsOf(pts);
    }
    if (gt)
    {
        for (const auto& s : gt->path) p.true_path.emplace_back(s.x, s.y);
        for (const auto& l : gt->landmarks) p.true_landmarks.emplace_back(l.x, l.y);
    }
    return p;
}

eval::MetricsJson computeMetrics(const DenseSlam& slam, const GroundTruth& gt, double run_seconds)
{
    eval::MetricsJson j;
    j.set("run_seconds", run_seconds);
    j.set("steps", static_cast<unsigned long>(slam.path().size()));
    j.set("landmarks_estimated", static_cast<unsigned long>(slam.ekf().numLandmarks()));
    if (slam.options().landmark_source != DenseSlam::LandmarkSource::BearingRange)
    {
        const auto& st = slam.stats();
        const auto by = landmarksByFeature(slam);
        auto& ej = j.object("extraction");
        ej.set("scans", static_cast<unsigned long>(st.scans));
        ej.set("observations", static_cast<unsigned long>(st.extracted));
        ej.set("reflectors", static_cast<unsigned long>(st.reflectors_extracted));
        ej.set("trees", static_cast<unsigned long>(st.trees_extracted));
        ej.set("trees_duplicate", static_cast<unsigned long>(st.trees_duplicate));
        ej.set("landmarks_reflector_only", static_cast<unsigned long>(by.reflector_only));
        ej.set("landmarks_tree_only", static_cast<unsigned long>(by.tree_only));
        ej.set("landmarks_reflector_and_tree", static_cast<unsigned long>(by.both));
    }

    if (!gt.path.empty())
    {
        eval::TrajectoryEvaluator::Options to;
        to.association = gt.path_has_timestamps ? eval::TrajectoryEvaluator::Association::Interpolate
                                                : eval::TrajectoryEvaluator::Association::Index;
        const auto traj = eval::TrajectoryEvaluator(to).evaluate(estimatedPath(slam), gt.path);
        eval::writeTrajectoryMetrics(j.object("path"), traj);

        // Vehicle NEES per matched step (3 DOF), against the single-run 95% band.
        const std::vector<double> nees_series = vehicleNeesSeries(slam, gt);
        const auto band = eval::averageNeesBounds(3, 1, 0.95);
        double sum = 0;
        size_t n = 0;
        for (double v : nees_series)
            if (std::isfinite(v)) sum += v, ++n;
        auto& nj = j.object("vehicle_nees");
        nj.set("mean", n ? sum / n : std::nan(""));
        nj.set("steps", static_cast<unsigned long>(n));
        nj.set("band_lower", band.lower);
        nj.set("band_upper", band.upper);
        nj.set("fraction_inside_band", eval::fractionInsideBounds(nees_series, band));
    }
    if (!gt.landmarks.empty())
    {
        eval::LandmarkEvaluator::Options lo;
        lo.association = landmarkAssociationFor(slam);
        const auto lr = eval::LandmarkEvaluator(lo).evaluate(estimatedLandmarks(slam.ekf()), gt.landmarks);
        eval::writeLandmarkMetrics(j.object("landmarks"), lr);
        std::vector<double> lm_nees;
        for (const auto& m : lr.matches)
            if (m.has_nees && m.nees.ok()) lm_nees.push_back(m.nees.value);
        const auto band = eval::averageNeesBounds(2, 1, 0.95);
        auto& lj = j.object("landmark_nees");
        lj.set("band_lower", band.lower);
        lj.set("band_upper", band.upper);
        lj.set("fraction_inside_band", eval::fractionInsideBounds(lm_nees, band));
    }
    return j;
}

eval::MetricsJson evaluateResultFiles(const std::string& path_tum, const std::string& landmarks_csv,
                                      const GroundTruth& gt)
{
    eval::MetricsJson j;
    if (!path_tum.empty() && !gt.path.empty())
    {
        eval::TrajectoryEvaluator::Options to;
        to.association = gt.path_has_timestamps ? eval::TrajectoryEvaluator::Association::Interpolate
                                                : eval::TrajectoryEvaluator::Association::Index;
        const auto traj = eval::TrajectoryEvaluator(to).evaluate(core::readTum(path_tum), gt.path);
        eval::writeTrajectoryMetrics(j.object("path"), traj);
    }
    if (!landmarks_csv.empty() && !gt.landmarks.empty())
    {
        const auto recs = core::readLandmarksCsv(landmarks_csv);
        const bool has_cov = !recs.empty() && recs.front().extra.size() >= 3;
        const auto est = eval::landmarkEstimatesFromRecords(recs, has_cov ? 0 : -1);
        const auto lr = eval::LandmarkEvaluator(eval::LandmarkEvaluator::Options{}).evaluate(est, gt.landmarks);
        eval::writeLandmarkMetrics(j.object("landmarks"), lr);
    }
    return j;
}

void writeTiming(const std::vector<FrameTiming>& timing, const std::string& file)
{
    std::ofstream f(file);
    if (!f) throw std::runtime_error("cannot write '" + file + "'");
    f << "entry,landmarks,observations,seconds\n" << std::setprecision(9);
    for (const auto& t : timing)
        f << t.entry << ',' << t.landmarks << ',' << t.observations << ',' << t.seconds << '\n';
    if (!f) throw std::runtime_error("error writing '" + file + "'");
}

namespace
{
// One line per enabled layer: what it holds and its memory.
void writeLayerSummary(std::ostream& f, const DenseSlam& slam)
{
    const auto* hybrid = slam.hybridMap();
    const auto items = hybrid->sizeByKind();
    const auto bytes = hybrid->memoryBytesByKind();
    for (const std::string& kind : hybrid->enabledKinds())
    {
        const size_t n = valueOr0(items, kind);
        f << std::setprecision(1) << "layer " << std::left << std::setw(15) << kind << std::right;
        if (kind == dense::PointsLayer::kKind)
            f << n << " points";
        else if (kind == dense::OccupancyLayer::kKind)
        {
            const CoarsenSummary c = coarsenSummary(slam);
            f << n << " cells updated, regions coarse " << c.coarse << " / fine " << c.fine;
        }
        else if (kind == dense::ParticlesLayer::kKind)
        {
            const ParticleWeights w = particleWeights(renderParticles(slam));
            f << n << " particles (w > 0.8: " << 100 * w.fraction(w.above)
              << "%, w < 0.5: " << 100 * w.fraction(w.below) << "%)";
        }
        else if (kind == dense::SogLayer::kKind)
            f << n << " Gaussians";
        else if (kind == dense::PropertyLayer::kKind)
            f << n << " cells with a value"
              << (n == 0 && slam.stats().returns_stored > 0 ? " (the scans carry no intensities)"
                                                            : "");
        else
            f << n << " items";
        f << ", " << valueOr0(bytes, kind) / 1024.0 << " KiB\n" << std::setprecision(3);
    }
}
}  // namespace

void writeSummary(const DenseSlam& slam, double run_seconds, size_t entries, const std::string& file)
{
    std::ofstream f(file);
    if (!f) throw std::runtime_error("cannot write '" + file + "'");
    const auto& s = slam.stats();
    const auto pose = slam.ekf().vehiclePose();
    f << std::fixed << std::setprecision(3) << "rawlog entries       " << entries << "\n"
      << "predictions          " << s.predictions << "\n"
      << "sensory frames       " << s.frames << "\n"
      << "observations         " << s.observations << " (associated " << s.associated
      << ", created " << s.created << ", gate rejects " << s.rejected_gate << ", ambiguous "
      << s.ambiguous << ", numeric rejects " << s.rejected_numeric << ")\n"
      << "skipped readings     " << s.skipped_invalid << "\n"
      << "laser scans          " << s.scans << " (landmarks extracted " << s.extracted;
    if (s.reflectors_extracted + s.trees_extracted > 0)
        f << "; reflectors " << s.reflectors_extracted << ", trees " << s.trees_extracted
          << ", trees dropped as a reflector's object " << s.trees_duplicate;
    f << ")\n"
      << "landmarks in map     " << slam.ekf().numLandmarks();
    if (!slam.landmarkFeatures().empty())
    {
        const auto by = landmarksByFeature(slam);
        f << " (observed as reflector only " << by.reflector_only << ", as tree only "
          << by.tree_only << ", as both " << by.both << ")";
    }
    f << "\n"
      << "final pose           " << pose[0] << " " << pose[1] << " " << pose[2] << "\n"
      << "run time [s]         " << run_seconds << "\n";
    if (const auto* p = slam.partition())
        f << "regions (LTR)        " << p->size() << " (created " << s.regions_created << ", removed "
          << s.regions_removed << ", partition updates " << s.partition_updates << ")\n"
          << "dense scans          " << s.dense_scans << " (returns stored " << s.returns_stored
          << ", outside regions " << s.returns_outside << " [kept by the fallback "
          << s.returns_fallback << ", in the delayed store " << s.delayed_stored << ", dropped "
          << s.returns_dropped << "], withheld " << s.returns_withheld << " [kept by the fallback "
          << s.returns_withheld_fallback << "]"
          << "; no-return beams as free space " << s.no_return_beams << ", failed readings "
          << s.failed_readings << ")\n"
          << "outside, why (final) " << [&] {
                 // ltr/outside_causes.h, on the final map; in brackets: of the dropped ones.
                 const auto c = outsideCauses(slam);
                 std::ostringstream o;
                 for (size_t k = 0; k < c.all.n.size(); ++k)
                     o << (k ? ", " : "") << ltr::toString(static_cast<ltr::OutsideCause>(k)) << " "
                       << c.all.n[k] << " [" << c.dropped.n[k] << "]";
                 return o.str();
             }() << "\n"
          << "virtual landmarks    " << slam.virtualLandmarkIds().size() << " (created "
          << s.virtual_landmarks << ", apexes rejected " << s.virtual_rejected << ")\n";
    if (const auto* store = slam.delayedStore())
        f << "delayed store        stored " << s.delayed_stored << ", fused " << s.delayed_fused
          << ", waiting " << store->numStoredPoints() << "; not stored: outside potential regions "
          << s.delayed_outside_potential << ", over budget " << s.delayed_thinned
          << "; evicted " << s.delayed_evicted << ", lost " << s.delayed_lost << "\n";
    if (slam.hybridMap()) writeLayerSummary(f, slam);
    if (slam.classicGrid()) f << "classic grid         on\n";
    if (!f) throw std::runtime_error("error writing '" + file + "'");
}

}  // namespace hymm::denseslam
