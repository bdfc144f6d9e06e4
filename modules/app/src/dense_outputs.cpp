// The dense maps of a run: their files (writeDenseOutputs) and their counters and outline
// metrics (writeDenseMetrics). What is per layer kind comes from the
// kind's output hooks (dense::LayerKind::outputs).
#include <hymm/dense/CHybridMetricMap.h>
#include <hymm/app/slam_outputs.h>
#include <hymm/core/serialized_file.h>
#include <hymm/dense/map_images.h>
#include <hymm/eval/se2_alignment.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>

#include <cmath>
#include <limits>

#include "output_helpers.h"
#include "return_books.h"

namespace hymm::app
{
namespace
{
constexpr double kAlignmentGate = 3.0;  //!< [m] estimated-true landmark pairs for the map alignment

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

// Counts and memory of every layer (metrics.json "dense"; also without --gt-objects).
void writeLayerCounts(eval::MetricsJson& dj, const DenseSlam& slam)
{
    const auto* hybrid = slam.hybridMap();
    const auto items = hybrid->sizeByKind();
    const auto bytes = hybrid->memoryBytesByKind();
    auto& mj = dj.object("memory_bytes_by_kind");
    const auto context = layerOutputContext(slam);
    for (const auto* k : enabledLayerKinds(slam))
    {
        mj.set(k->name, static_cast<unsigned long>(valueOr0(bytes, k->name)));
        auto& lj = dj.object(k->name);
        lj.set("items", static_cast<unsigned long>(valueOr0(items, k->name)));
        lj.set("memory_bytes", static_cast<unsigned long>(valueOr0(bytes, k->name)));
        if (k->outputs.counts)
            for (const auto& counter : k->outputs.counts(context)) setCounter(lj, counter);
    }
}

// Region, return and delayed-store counters, then the layers' counts.
void writeRegionCounters(eval::MetricsJson& dj, const DenseSlam& slam)
{
    const auto& st = slam.stats();
    dj.set("regions", static_cast<unsigned long>(slam.partition()->size()));
    dj.set("regions_created", static_cast<unsigned long>(st.regions_created));
    dj.set("regions_removed", static_cast<unsigned long>(st.regions_removed));
    dj.set("virtual_landmarks", static_cast<unsigned long>(slam.virtualLandmarkIds().size()));
    dj.set("returns_stored", static_cast<unsigned long>(st.returns_stored));
    dj.set("returns_outside", static_cast<unsigned long>(st.returns_outside));
    dj.set("returns_withheld", static_cast<unsigned long>(st.returns_withheld));
    writeReturnBooks(dj, slam);
    dj.set("no_return_beams", static_cast<unsigned long>(st.no_return_beams));
    dj.set("failed_readings", static_cast<unsigned long>(st.failed_readings));
    if (slam.delayedStore())
    {
        auto& sj = dj.object("delayed_store");
        sj.set("stored", static_cast<unsigned long>(st.delayed_stored));
        sj.set("fused", static_cast<unsigned long>(st.delayed_fused));
        sj.set("fused_fallback", static_cast<unsigned long>(st.delayed_fused_fallback));
        sj.set("waiting", static_cast<unsigned long>(slam.delayedStore()->numStoredPoints()));
        sj.set("outside_potential", static_cast<unsigned long>(st.delayed_outside_potential));
        sj.set("thinned", static_cast<unsigned long>(st.delayed_thinned));
        sj.set("evicted", static_cast<unsigned long>(st.delayed_evicted));
        sj.set("lost", static_cast<unsigned long>(st.delayed_lost));
    }
    dj.set("memory_bytes", static_cast<unsigned long>(slam.hybridMap()->memoryBytes()));
    writeLayerCounts(dj, slam);
}

// The filter's frame is fixed by the start pose, but heading error gathered before the
// first landmarks are mapped is never observable again: the whole map, landmarks and
// dense content alike, carries a common rigid error. Scoring the maps also after the
// least-squares SE(2) fit of the landmark map onto the true landmarks (one transform for
// every map, the classic grid included, since all share the filter's frame) separates
// that common part from the shape of each map. Fills truth.*_est when there is a fit.
void writeLandmarkAlignment(eval::MetricsJson& dj, const DenseSlam& slam,
                            const std::vector<TrueTrunk>& true_landmarks, TrueSurfaces& truth)
{
    const LandmarkPairs pairs = nearestPairs(slam, true_landmarks, kAlignmentGate);
    const auto t = eval::alignSE2(pairs.est, pairs.truth);
    if (!t || pairs.est.size() < 3) return;
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

// The fallback's content alone (returns kept outside every region in the frame of a
// nearby region): its error includes the extrapolated affine maps, so it is scored apart.
void writeFallbackMetrics(eval::MetricsJson& dj, const DenseSlam& slam, const TrueSurfaces& truth)
{
    const auto* hybrid = slam.hybridMap();
    if (!hybrid || hybrid->fallbackTiles() == 0) return;
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
        setOutlineMetrics(fj.object("occupancy"), dense::occupiedCellCentres(grid, dense::kOccupiedProbability),
                          truth);
    }
}
}  // namespace

void writeDenseOutputs(const DenseSlam& slam, const std::string& dir, bool png)
{
    const std::string d = dir.empty() || dir.back() == '/' ? dir : dir + "/";
    if (const auto* partition = slam.partition()) partition->saveToFile(d + "regions.txt");
    for (const auto* k : enabledLayerKinds(slam)) k->outputs.write(layerOutputContext(slam), d, png);
    if (const auto* classic = slam.classicGrid())
    {
        mrpt::maps::COccupancyGridMap2D grid;
        classic->toOccupancyGridMap(grid);
        core::writeSerializedGz(dense::freeProbabilityGrid(grid), d + "classic_grid.gridmap");  // P(free)
        if (png) dense::saveOccupancyPng(grid, d + "classic_grid.png");
    }
}

std::vector<TrueTrunk> trueTrunks(const std::vector<io::LandmarkRecord>& landmarks)
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
    if (slam.partition()) writeRegionCounters(dj, slam);
    if (outlines.empty()) return;
    TrueSurfaces truth;
    truth.outlines = outlines;
    truth.surfaces = outlines;
    for (const auto& t : true_landmarks) truth.surfaces.push_back(dense::circlePolygon(t.centre, t.radius));
    writeLandmarkAlignment(dj, slam, true_landmarks, truth);
    for (const auto* k : enabledLayerKinds(slam))
        setOutlineMetrics(dj.object(k->name), k->outputs.scored_points(layerOutputContext(slam)), truth);
    writeFallbackMetrics(dj, slam, truth);
    if (const auto* classic = slam.classicGrid())
    {
        mrpt::maps::COccupancyGridMap2D grid;
        classic->toOccupancyGridMap(grid);
        setOutlineMetrics(dj.object("classic_grid"),
                          dense::occupiedCellCentres(grid, dense::kOccupiedProbability), truth);
    }
}

}  // namespace hymm::app
