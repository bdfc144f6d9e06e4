#include "hymm/dense/SogLayer.h"

#include "hymm/dense/geometry.h"
#include "text_io.h"

#include <hymm/core/config_utils.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CPointsMap.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <unordered_map>

namespace hymm::dense
{
namespace
{
/** Current-frame Gaussian with its information matrix, for surface evaluation. */
struct CurrentGaussian
{
    Eigen::Vector2d mean;
    Eigen::Matrix2d info;
    Eigen::Vector2d half;  // half-size of the cutoff box
};

CurrentGaussian toCurrent(
    const SogLayer::Gaussian& g, const hymm::ltr::AffineRegionMap& m, double cutoff_sigmas)
{
    const Eigen::Matrix2d p = transformCovariance(m.linear(), g.cov);
    return {m.mapPoint(g.mean), p.inverse(),
            cutoff_sigmas * Eigen::Vector2d(std::sqrt(p(0, 0)), std::sqrt(p(1, 1)))};
}

/** Peak-1 Gaussian (Fig. 4.12 b) at `x`. */
double peakOne(const CurrentGaussian& g, const Eigen::Vector2d& x)
{
    const Eigen::Vector2d d = x - g.mean;
    return std::exp(-0.5 * d.dot(g.info * d));
}

bool isCovariance(const Eigen::Matrix2d& p)
{
    return p.allFinite() && p(0, 1) == p(1, 0) && p(0, 0) > 0 && p(1, 1) > 0 && p.determinant() > 0;
}

/** Indices of the first `n` Gaussians by hash cell of side `cell`. */
using CellIndex = std::unordered_map<std::int64_t, std::vector<size_t>>;
CellIndex indexOf(const std::vector<SogLayer::Gaussian>& gs, size_t n, double cell)
{
    CellIndex index;
    for (size_t i = 0; i < n; ++i) index[pointCellKey(gs[i].mean, cell)].push_back(i);
    return index;
}

/** The entry of `gs` (as indexed) nearest to p within `cell`, or `none`. */
size_t nearest(const CellIndex& index, const std::vector<SogLayer::Gaussian>& gs, const Eigen::Vector2d& p,
               double cell, size_t none)
{
    size_t best = none;
    double best_d2 = cell * cell;
    for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (std::int64_t dy = -1; dy <= 1; ++dy)
        {
            const auto it = index.find(pointCellKey(p, cell, dx, dy));
            if (it == index.end()) continue;
            for (const size_t i : it->second)
                if (const double d2 = (gs[i].mean - p).squaredNorm(); d2 < best_d2)
                {
                    best_d2 = d2;
                    best = i;
                }
        }
    return best;
}
}  // namespace

double majorSigma(const Eigen::Matrix2d& cov)
{
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov, Eigen::EigenvaluesOnly);
    return std::sqrt(std::max(0.0, es.eigenvalues()(1)));
}

hymm::core::OptionTable SogLayer::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("range_std_m", range_std_m, "m", above(0, 10), "sensor range noise when the scan carries none (Table 4.1); hymm-slam: `[Laser] std_range_m`");
    t.real("bearing_std_deg", bearing_std_deg, "deg", openInterval(0, 60),
           "sensor bearing noise when the scan carries none (Table 4.1); hymm-slam: `[Laser] std_bearing_deg`");
    t.real("d_min_m", d_min_m, "m", above(0, 100), "fusion distance of the means (Sec. 4.3.3)");
    t.real("k", k, "", above(0, 100), "Eq. 4.18 factor (Sec. 4.3.3)");
    t.choice("fusion_rule", fusion_rule, {{"average", FusionRule::Average}, {"product", FusionRule::Product}},
             "Eq. 4.17-4.20 average, or the Bayesian product");
    t.real("cutoff_sigmas", cutoff_sigmas, "sigmas", above(0, 100), "surface rendering ignores a Gaussian beyond this");
    t.flag("absorb_within_d_min", absorb_within_d_min,
           "a scan Gaussian no map Gaussian took is fused into the nearest one within `d_min_m` instead of being "
           "added, so revisits do not add components (false = the thesis, Sec. 4.3.2)");
    t.real("merge_within_m", merge_within_m, "m", between(0, 100),
           "a map Gaussian moved by an insert's fusions that lies within this of another is merged with it (the older "
           "stays, the younger goes), so fused means that drift together become one component (0 = the thesis, "
           "Sec. 4.3.2); at most `d_min_m`");
    t.real("max_mean_per_cell", max_mean_per_cell, "", between(0, 1e6),
           "a region or fallback tile keeps at most this many components per square cell of side `d_min_m` that "
           "their means occupy: beyond, the closest pairs are merged into one Gaussian with their mean and "
           "covariance (the subsampling Sec. 4.3.3 leaves out), so revisits do not add components where the area "
           "is covered; 0 = unbounded (the thesis)");
    t.real("max_range_m", max_range_m, "m", between(0, 1e6),
           "returns farther than this from the sensor add no Gaussian; the other layers still take them (0 = every "
           "return the map is given, the thesis)");
    return t;
}

void SogLayer::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void SogLayer::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void SogLayer::Options::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    const auto positive = [&](const char* key, double v) {
        if (!(v > 0) || !std::isfinite(v)) throwConfigError(s, key, std::to_string(v), "must be finite and > 0");
    };
    positive("range_std_m", range_std_m);
    positive("bearing_std_deg", bearing_std_deg);
    positive("d_min_m", d_min_m);
    positive("k", k);
    positive("cutoff_sigmas", cutoff_sigmas);
    if (!(merge_within_m >= 0) || merge_within_m > d_min_m)
        throwConfigError(s, "merge_within_m", std::to_string(merge_within_m), "must be in [0, d_min_m]");
    if (!(max_mean_per_cell >= 0) || !std::isfinite(max_mean_per_cell))
        throwConfigError(s, "max_mean_per_cell", std::to_string(max_mean_per_cell), "must be finite and >= 0");
    if (!(max_range_m >= 0) || !std::isfinite(max_range_m))
        throwConfigError(s, "max_range_m", std::to_string(max_range_m), "must be finite and >= 0");
}

RangeBearingNoise SogLayer::Options::noise() const { return {range_std_m, bearing_std_deg * M_PI / 180.0}; }

SogLayer::SogLayer(const Options& options) : options_(options) { options_.validate(); }

std::vector<SogLayer::Gaussian> SogLayer::observationGaussians(const RegionScan& scan) const
{
    const RangeBearingNoise noise = effectiveNoise(scan, options_.noise());
    const Eigen::Matrix2d& to_ref = scan.to_reference_linear;
    if (!to_ref.allFinite() || std::abs(to_ref.determinant()) < 1e-12)
        throw std::invalid_argument("SogLayer::insert: to_reference_linear must be finite and invertible");
    const Eigen::Matrix2d to_cur = to_ref.inverse();
    std::vector<Gaussian> out;
    out.reserve(scan.hits.size());
    for (const Eigen::Vector2d& h : scan.hits)
    {
        if (!h.allFinite()) throw std::invalid_argument("SogLayer::insert: a return is not finite");
        const Eigen::Vector2d d = to_cur * (h - scan.sensor);
        const double r = d.norm();
        if (!(r > 0)) continue;
        if (options_.max_range_m > 0 && r > options_.max_range_m) continue;
        // Eq. 4.15-4.16 in the current frame, then into the reference frame.
        const Eigen::Matrix2d p = polarToCartesianCovariance(r, std::atan2(d.y(), d.x()), noise);
        out.push_back({h, transformCovariance(to_ref, p)});
    }
    return out;
}

SogLayer::Gaussian SogLayer::fuse(const Gaussian& priori, const Gaussian& obs) const
{
    if (options_.fusion_rule == FusionRule::Product)
    {
        const mrpt::poses::CPoint2DPDFGaussian a(
            mrpt::poses::CPoint2D(priori.mean.x(), priori.mean.y()), mrpt::math::CMatrixDouble22(priori.cov));
        const mrpt::poses::CPoint2DPDFGaussian b(
            mrpt::poses::CPoint2D(obs.mean.x(), obs.mean.y()), mrpt::math::CMatrixDouble22(obs.cov));
        mrpt::poses::CPoint2DPDFGaussian c;
        c.bayesianFusion(a, b);
        const Eigen::Matrix2d p = c.cov.asEigen();
        return {Eigen::Vector2d(c.mean.x(), c.mean.y()), 0.5 * (p + p.transpose())};
    }
    Gaussian g;
    g.mean = 0.5 * (priori.mean + obs.mean);  // Eq. 4.17
    if (majorSigma(priori.cov) + majorSigma(obs.cov) <= options_.k * options_.d_min_m)  // Eq. 4.18
        g.cov = priori.cov + obs.cov;  // Eq. 4.19
    else
        g.cov = priori.cov;  // Eq. 4.20
    return g;
}

void SogLayer::insert(const RegionScan& scan)
{
    if (scan.hits.empty()) return;
    const std::vector<Gaussian> obs = observationGaussians(scan);
    // Neighbours closer than d_min are found in hash grids of cell d_min (step 3).
    const double cell = options_.d_min_m;
    // Each map Gaussian fuses its nearest scan Gaussian.
    const CellIndex index = indexOf(obs, obs.size(), cell);
    std::vector<char> used(obs.size(), 0);
    const size_t prior = gaussians_.size();
    std::vector<char> moved(prior, 0);
    for (size_t j = 0; j < prior; ++j)
    {
        Gaussian& g = gaussians_[j];
        const size_t best = nearest(index, obs, g.mean, cell, obs.size());
        if (best == obs.size()) continue;
        g = fuse(g, obs[best]);
        used[best] = 1;
        moved[j] = 1;
    }
    if (options_.absorb_within_d_min && prior > 0)
    {
        // The unused scan Gaussians near a map Gaussian join it (the header: revisits).
        // The map Gaussian may move a little with each fusion; the index keeps its cell at
        // the time of the lookup, which only matters within d_min.
        const CellIndex map_index = indexOf(gaussians_, prior, cell);
        for (size_t i = 0; i < obs.size(); ++i)
        {
            if (used[i]) continue;
            const size_t best = nearest(map_index, gaussians_, obs[i].mean, cell, prior);
            if (best == prior) continue;
            gaussians_[best] = fuse(gaussians_[best], obs[i]);
            used[i] = 1;
            moved[best] = 1;
        }
    }
    if (options_.merge_within_m > 0 && prior > 1) mergeMoved(prior, moved);
    const size_t kept = gaussians_.size();
    for (size_t i = 0; i < obs.size(); ++i)
        if (!used[i]) gaussians_.push_back(obs[i]);
    // Only births can take a region over its bound (moves may shrink the area a little;
    // the next birth sees it): a mature region is not walked once more per scan.
    if (gaussians_.size() > kept) capComponents();
}

void SogLayer::mergeMoved(size_t prior, const std::vector<char>& moved)
{
    const double cell = options_.merge_within_m;
    const CellIndex index = indexOf(gaussians_, prior, cell);
    // Of two Gaussians within merge_within_m the older one stays as it is and the younger
    // goes (the vector is in birth order: inserts append, removals keep the order). The
    // older one has fused more returns; an average with the younger (Eq. 4.17 is meant for
    // a map and a scan Gaussian) would pull it halfway towards a noise tail each time
    // (a test: 0.077 m instead of 0.041 m mean distance from the wall).
    std::vector<char> gone(prior, 0);
    for (size_t i = 0; i < prior; ++i)
    {
        if (!moved[i] || gone[i]) continue;
        const Eigen::Vector2d p = gaussians_[i].mean;
        for (std::int64_t dx = -1; dx <= 1 && !gone[i]; ++dx)
            for (std::int64_t dy = -1; dy <= 1 && !gone[i]; ++dy)
            {
                const auto it = index.find(pointCellKey(p, cell, dx, dy));
                if (it == index.end()) continue;
                for (const size_t j : it->second)
                    if (j != i && !gone[j] && (gaussians_[j].mean - p).squaredNorm() < cell * cell)
                    {
                        gone[std::max(i, j)] = 1;
                        if (j < i) break;  // i itself went
                    }
            }
    }
    size_t out = 0;
    for (size_t i = 0; i < gaussians_.size(); ++i)
        if (i >= prior || !gone[i]) gaussians_[out++] = gaussians_[i];
    gaussians_.resize(out);
}

size_t SogLayer::memoryBytes() const { return sizeof(*this) + gaussians_.capacity() * sizeof(Gaussian); }

mrpt::poses::CPoint2DPDFGaussian SogLayer::gaussianAt(
    size_t i, const hymm::ltr::AffineRegionMap& reference_to_current) const
{
    const Gaussian& g = gaussians_.at(i);
    const Eigen::Vector2d m = reference_to_current.mapPoint(g.mean);
    return mrpt::poses::CPoint2DPDFGaussian(
        mrpt::poses::CPoint2D(m.x(), m.y()),
        mrpt::math::CMatrixDouble22(transformCovariance(reference_to_current.linear(), g.cov)));
}

void SogLayer::addSurface(const hymm::ltr::AffineRegionMap& reference_to_current, ScalarField& field) const
{
    for (const Gaussian& g : gaussians_)
    {
        const CurrentGaussian c = toCurrent(g, reference_to_current, options_.cutoff_sigmas);
        const double res = field.resolution;
        const int x0 = std::max(0, static_cast<int>(std::floor((c.mean.x() - c.half.x() - field.origin.x()) / res)));
        const int y0 = std::max(0, static_cast<int>(std::floor((c.mean.y() - c.half.y() - field.origin.y()) / res)));
        const int x1 = std::min(field.sizeX() - 1, static_cast<int>(std::floor((c.mean.x() + c.half.x() - field.origin.x()) / res)));
        const int y1 = std::min(field.sizeY() - 1, static_cast<int>(std::floor((c.mean.y() + c.half.y() - field.origin.y()) / res)));
        for (int iy = y0; iy <= y1; ++iy)
            for (int ix = x0; ix <= x1; ++ix) field.values(iy, ix) += peakOne(c, field.cellCentre(ix, iy));
    }
}

std::vector<std::vector<Eigen::Vector2d>> SogLayer::ellipses(
    const hymm::ltr::AffineRegionMap& reference_to_current, int points) const
{
    if (points < 3) throw std::invalid_argument("SogLayer::ellipses: need >= 3 points per ellipse");
    std::vector<std::vector<Eigen::Vector2d>> out;
    out.reserve(gaussians_.size());
    for (const Gaussian& g : gaussians_)
    {
        // 1-sigma contour: m + V diag(sqrt(lambda)) (cos t, sin t).
        const Eigen::Matrix2d p = transformCovariance(reference_to_current.linear(), g.cov);
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(p);
        const Eigen::Matrix2d l = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
        const Eigen::Vector2d m = reference_to_current.mapPoint(g.mean);
        std::vector<Eigen::Vector2d> poly;
        for (int k = 0; k < points; ++k)
        {
            const double t = 2 * M_PI * k / points;
            poly.push_back(m + l * Eigen::Vector2d(std::cos(t), std::sin(t)));
        }
        out.push_back(std::move(poly));
    }
    return out;
}

void SogLayer::renderInto(const hymm::ltr::AffineRegionMap& reference_to_current, mrpt::maps::CMetricMap& out) const
{
    if (auto* pts = dynamic_cast<mrpt::maps::CPointsMap*>(&out))
    {
        for (const Gaussian& g : gaussians_)
        {
            const Eigen::Vector2d m = reference_to_current.mapPoint(g.mean);
            pts->insertPoint(static_cast<float>(m.x()), static_cast<float>(m.y()));
        }
        return;
    }
    auto* og = dynamic_cast<mrpt::maps::COccupancyGridMap2D*>(&out);
    if (!og)
        throw std::invalid_argument(
            std::string("SogLayer::renderInto: cannot draw Gaussians into a ") + out.GetRuntimeClass()->className);
    if (gaussians_.empty()) return;
    // This region's sum on a field aligned with the grid's cells, then max-merged.
    const double res = og->getResolution();
    ScalarField f;
    f.origin = Eigen::Vector2d(og->getXMin(), og->getYMin());
    f.resolution = res;
    f.values = Eigen::MatrixXd::Zero(og->getSizeY(), og->getSizeX());
    addSurface(reference_to_current, f);
    for (int iy = 0; iy < f.sizeY(); ++iy)
        for (int ix = 0; ix < f.sizeX(); ++ix)
        {
            const double v = std::min(1.0, f.values(iy, ix));
            if (v <= 0) continue;
            if (v > og->getCell(ix, iy)) og->setCell(ix, iy, static_cast<float>(v));
        }
}

void SogLayer::save(std::ostream& out) const
{
    out << "sog " << gaussians_.size() << '\n' << std::hexfloat;
    for (const Gaussian& g : gaussians_)
        out << g.mean.x() << ' ' << g.mean.y() << ' ' << g.cov(0, 0) << ' ' << g.cov(0, 1) << ' ' << g.cov(1, 1)
            << '\n';
    out << std::defaultfloat;
}

void SogLayer::load(std::istream& in)
{
    constexpr const char* kWho = "SogLayer::load";
    const size_t n = text_io::readHeader(in, "sog", kWho);
    std::vector<Gaussian> gs;
    gs.reserve(n);
    for (size_t i = 0; i < n; ++i)
    {
        Gaussian g;
        g.mean.x() = text_io::readNumber(in, kWho);
        g.mean.y() = text_io::readNumber(in, kWho);
        g.cov(0, 0) = text_io::readNumber(in, kWho);
        g.cov(0, 1) = g.cov(1, 0) = text_io::readNumber(in, kWho);
        g.cov(1, 1) = text_io::readNumber(in, kWho);
        if (!g.mean.allFinite() || !isCovariance(g.cov))
            throw std::runtime_error(std::string(kWho) + ": Gaussian " + std::to_string(i) +
                                     " has a non-finite mean or a covariance that is not positive definite");
        gs.push_back(g);
    }
    gaussians_ = std::move(gs);
}

}  // namespace hymm::dense
