#include "hymm/dense/ParticlesLayer.h"

#include "region_seed.h"

#include "hymm/dense/geometry.h"
#include "text_io.h"

#include <mrpt/maps/CPointsMap.h>
#include <mrpt/maps/CPointsMapXYZI.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <unordered_map>

namespace hymm::dense
{
namespace
{
// Beyond 3 sigma in bearing the cone factor a(phi) of the occupancy model is < 0.012:
// beams farther away cannot move a particle's weight noticeably.
constexpr double kConeSigmas = 3.0;
// A model value above 0.5 + this means the particle sits in a return's peak.
constexpr double kPeakTol = 1e-9;

/** Points hashed on cells of `cell` [m]: is any closer than `cell` to a query point? */
class PointHash
{
public:
    PointHash(const std::vector<Eigen::Vector2d>& points, double cell) : cell_(cell)
    {
        for (const Eigen::Vector2d& p : points) cells_[key(p, 0, 0)].push_back(p);
    }
    /** Some point strictly closer than the cell size (the nearest such point lies in
     *  the query's cell or one of its 8 neighbours). */
    bool anyWithinCell(const Eigen::Vector2d& q) const
    {
        const double d2 = cell_ * cell_;
        for (std::int64_t dx = -1; dx <= 1; ++dx)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
            {
                const auto it = cells_.find(key(q, dx, dy));
                if (it == cells_.end()) continue;
                for (const Eigen::Vector2d& p : it->second)
                    if ((p - q).squaredNorm() < d2) return true;
            }
        return false;
    }

private:
    std::int64_t key(const Eigen::Vector2d& p, std::int64_t dx, std::int64_t dy) const
    {
        return pointCellKey(p, cell_, dx, dy);
    }
    double cell_;
    std::unordered_map<std::int64_t, std::vector<Eigen::Vector2d>> cells_;
};

void checkFinite(const RegionScan& scan)
{
    if (!scan.to_reference_linear.allFinite() || std::abs(scan.to_reference_linear.determinant()) < 1e-12)
        throw std::invalid_argument("ParticlesLayer::insert: to_reference_linear must be finite and invertible");
    if (!scan.sensor.allFinite()) throw std::invalid_argument("ParticlesLayer::insert: sensor is not finite");
    for (const auto& h : scan.hits)
        if (!h.allFinite()) throw std::invalid_argument("ParticlesLayer::insert: a return is not finite");
    for (const auto& h : scan.shadow_returns)
        if (!h.allFinite()) throw std::invalid_argument("ParticlesLayer::insert: a shadow return is not finite");
}
}  // namespace

ParticlesLayer::ParticlesLayer(const Options& options, const hymm::ltr::TriangleFrame::Vertices& reference)
    : options_(options), noise_(options.noise())
{
    options_.validate();
    const auto seed = detail::regionSeedWords(static_cast<std::uint32_t>(options_.random_seed), reference);
    std::seed_seq seq(seed.begin(), seed.end());
    rng_.seed(seq);
}

void ParticlesLayer::insert(const RegionScan& scan)
{
    last_ = {};
    if (scan.empty()) return;
    checkFinite(scan);
    noise_ = effectiveNoise(scan, options_.noise());
    const Eigen::Matrix2d to_current = scan.to_reference_linear.inverse();

    const std::vector<Particle> samples = drawSamples(scan, to_current);
    std::vector<char> updated(particles_.size(), 0);
    const std::vector<Particle> fresh = associate(samples, updated);
    if (options_.free_space_update) freeSpaceUpdate(scan, to_current, updated);
    particles_.insert(particles_.end(), fresh.begin(), fresh.end());
    last_.added = fresh.size();
    prune();
}

std::vector<ParticlesLayer::Particle> ParticlesLayer::drawSamples(
    const RegionScan& scan, const Eigen::Matrix2d& to_current_linear)
{
    std::normal_distribution<double> n01(0.0, 1.0);
    std::vector<Particle> out;
    out.reserve(scan.hits.size() * static_cast<size_t>(options_.samples_per_return));
    for (const Eigen::Vector2d& h : scan.hits)
    {
        // Range and bearing of the return in the current (metric) frame.
        const Eigen::Vector2d d = to_current_linear * (h - scan.sensor);
        const double z_r = d.norm();
        if (!(z_r > 0)) continue;
        const double z_t = std::atan2(d.y(), d.x());
        for (int k = 0; k < options_.samples_per_return; ++k)
        {
            const double r = z_r + noise_.range_std_m * n01(rng_);
            const double t = z_t + noise_.bearing_std_rad * n01(rng_);
            if (!(r > 0)) continue;  // a sample behind the sensor has no meaning
            const double w = occupancyModel(r, t, z_r, z_t, true, noise_, options_.profile());  // Eq. 4.9
            const Eigen::Vector2d off_cur(r * std::cos(t), r * std::sin(t));
            out.push_back({scan.sensor + scan.to_reference_linear * off_cur, std::min(w, options_.max_weight)});
        }
    }
    last_.drawn = out.size();
    return out;
}

std::vector<ParticlesLayer::Particle> ParticlesLayer::associate(
    const std::vector<Particle>& samples, std::vector<char>& updated)
{
    // Hash grid of the new samples with cells of d_min: the nearest sample within d_min
    // of a point lies in its cell or one of the 8 neighbours.
    const double cell = options_.d_min_m;
    const auto cellOf = [cell](const Eigen::Vector2d& p) {
        return std::pair<std::int64_t, std::int64_t>{
            static_cast<std::int64_t>(std::floor(p.x() / cell)), static_cast<std::int64_t>(std::floor(p.y() / cell))};
    };
    std::unordered_map<std::int64_t, std::vector<size_t>> index;
    for (size_t i = 0; i < samples.size(); ++i)
    {
        const auto [cx, cy] = cellOf(samples[i].position);
        index[packCellKey(cx, cy)].push_back(i);
    }
    std::vector<char> used(samples.size(), 0);
    const double d2_min = options_.d_min_m * options_.d_min_m;
    for (size_t j = 0; j < particles_.size(); ++j)
    {
        Particle& pj = particles_[j];
        const auto [cx, cy] = cellOf(pj.position);
        size_t best = samples.size();
        double best_d2 = d2_min;
        for (std::int64_t dx = -1; dx <= 1; ++dx)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
            {
                const auto it = index.find(packCellKey(cx + dx, cy + dy));
                if (it == index.end()) continue;
                for (const size_t i : it->second)
                {
                    const double d2 = (samples[i].position - pj.position).squaredNorm();
                    if (d2 < best_d2)  // Eq. 4.10: strictly closer than d_min
                    {
                        best_d2 = d2;
                        best = i;
                    }
                }
            }
        if (best == samples.size()) continue;
        const Particle& si = samples[best];
        pj.weight = std::min(bayesOccupancyUpdate(pj.weight, si.weight), options_.max_weight);  // Eq. 4.11
        if (options_.position_averaging) pj.position = 0.5 * (pj.position + si.position);
        updated[j] = 1;
        used[best] = 1;
        ++last_.associated;
    }
    std::vector<Particle> fresh;
    for (size_t i = 0; i < samples.size(); ++i)
        if (!used[i]) fresh.push_back(samples[i]);  // Eq. 4.12
    return fresh;
}

void ParticlesLayer::scanBeams(
    const RegionScan& scan, const Eigen::Matrix2d& to_current_linear, std::vector<Beam>& beams,
    std::vector<Eigen::Vector2d>& returns) const
{
    beams.clear();
    returns.assign(scan.hits.begin(), scan.hits.end());
    beams.reserve(scan.rays.size() + scan.shadow_returns.size());
    const auto add = [&](const Eigen::Vector2d& end, bool hit) {
        const Eigen::Vector2d d = to_current_linear * (end - scan.sensor);
        const double range = d.norm();
        if (!(range > 0)) return;
        beams.push_back({std::atan2(d.y(), d.x()), range, hit});
        if (hit) returns.push_back(end);
    };
    for (const FreeRay& ray : scan.rays)
    {
        const bool known = ray.beam_end.allFinite();
        add(known ? ray.beam_end : ray.to, known ? ray.beam_hit : ray.ends_at_hit);
    }
    for (const Eigen::Vector2d& r : scan.shadow_returns) add(r, true);
    std::sort(beams.begin(), beams.end(), [](const Beam& a, const Beam& b) { return a.bearing < b.bearing; });
}

void ParticlesLayer::freeSpaceUpdate(
    const RegionScan& scan, const Eigen::Matrix2d& to_current_linear, const std::vector<char>& updated)
{
    std::vector<Beam> beams;
    std::vector<Eigen::Vector2d> returns;
    scanBeams(scan, to_current_linear, beams, returns);
    if (beams.empty()) return;
    const bool protect = options_.free_space_protection;
    const PointHash seen(protect ? returns : std::vector<Eigen::Vector2d>{}, options_.d_min_m);

    const double half = kConeSigmas * noise_.bearing_std_rad;
    const OccupancyProfile profile = options_.profile();
    for (size_t j = 0; j < particles_.size(); ++j)
    {
        if (updated[j]) continue;  // this scan's returns already spoke for it
        Particle& p = particles_[j];
        const Eigen::Vector2d d = to_current_linear * (p.position - scan.sensor);
        const double rho = d.norm();
        if (!(rho > 0)) continue;
        const double phi = std::atan2(d.y(), d.x());
        double p_lo = 0.5, p_hi = 0.5;
        const auto visit = [&](double lo, double hi) {
            auto it = std::lower_bound(
                beams.begin(), beams.end(), lo, [](const Beam& b, double v) { return b.bearing < v; });
            for (; it != beams.end() && it->bearing <= hi; ++it)
            {
                const double m = occupancyModel(rho, phi, it->range, it->bearing, it->hit, noise_, profile);
                p_lo = std::min(p_lo, m);
                p_hi = std::max(p_hi, m);
            }
        };
        if (half >= M_PI)
            visit(-M_PI, M_PI);
        else if (phi - half < -M_PI)
        {
            visit(phi - half + 2 * M_PI, M_PI);
            visit(-M_PI, phi + half);
        }
        else if (phi + half > M_PI)
        {
            visit(-M_PI, phi + half - 2 * M_PI);
            visit(phi - half, M_PI);
        }
        else
            visit(phi - half, phi + half);
        if (p_hi > 0.5 + kPeakTol || !(p_lo < 0.5)) continue;  // in a return's peak, or no free evidence
        if (protect && (seen.anyWithinCell(p.position) || hiddenBehindOwnBeams(beams, rho, phi, half)))
        {
            ++last_.free_protected;
            continue;
        }
        p.weight = bayesOccupancyUpdate(p.weight, p_lo);  // Eq. 4.11 with the free-space weight
        ++last_.free_updated;
    }
}

bool ParticlesLayer::hiddenBehindOwnBeams(const std::vector<Beam>& beams, double rho, double phi, double half)
{
    // The neighbours on either side, across the +-pi seam when the particle is past
    // the first or last bearing.
    const auto it =
        std::lower_bound(beams.begin(), beams.end(), phi, [](const Beam& b, double v) { return b.bearing < v; });
    const Beam& right = it != beams.end() ? *it : beams.front();
    const Beam& left = it != beams.begin() ? *(it - 1) : beams.back();
    const auto behind = [&](const Beam& b) {
        return b.hit && rho > b.range && std::abs(std::remainder(b.bearing - phi, 2 * M_PI)) <= half;
    };
    return behind(left) || behind(right);
}

void ParticlesLayer::prune()
{
    const size_t before = particles_.size();
    particles_.erase(
        std::remove_if(
            particles_.begin(), particles_.end(),
            [this](const Particle& p) { return p.weight < options_.min_weight; }),
        particles_.end());
    if (options_.max_per_cell > 0)
    {
        // Heaviest max_per_cell per d_min cell (see the header: revisits).
        const auto per_cell = static_cast<size_t>(options_.max_per_cell);
        const double cell = options_.d_min_m;
        std::unordered_map<std::int64_t, std::vector<size_t>> cells;
        cells.reserve(particles_.size() / per_cell + 1);
        for (size_t i = 0; i < particles_.size(); ++i)
            cells[pointCellKey(particles_[i].position, cell)].push_back(i);
        std::vector<char> drop(particles_.size(), 0);
        bool any = false;
        for (auto& [key, idx] : cells)
        {
            if (idx.size() <= per_cell) continue;
            // Ties by index: the same map on the same data.
            std::nth_element(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(per_cell), idx.end(),
                             [this](size_t a, size_t b) {
                                 return particles_[a].weight > particles_[b].weight ||
                                        (particles_[a].weight == particles_[b].weight && a < b);
                             });
            for (size_t k = per_cell; k < idx.size(); ++k) drop[idx[k]] = 1;
            any = true;
        }
        if (any)
        {
            size_t out = 0;
            for (size_t i = 0; i < particles_.size(); ++i)
                if (!drop[i]) particles_[out++] = particles_[i];
            particles_.resize(out);
        }
    }
    const auto cap = static_cast<size_t>(options_.max_particles);
    if (cap > 0 && particles_.size() > cap)
    {
        // Keep the heaviest: the layer exists to describe occupied structure (Sec. 4.2.1),
        // and a dropped free particle only returns its area to "unknown".
        std::nth_element(
            particles_.begin(), particles_.begin() + static_cast<std::ptrdiff_t>(cap), particles_.end(),
            [](const Particle& a, const Particle& b) { return a.weight > b.weight; });
        particles_.resize(cap);
    }
    last_.removed = before - particles_.size();
}

size_t ParticlesLayer::memoryBytes() const
{
    return sizeof(*this) + particles_.capacity() * sizeof(Particle);
}

void ParticlesLayer::renderInto(
    const hymm::ltr::AffineRegionMap& reference_to_current, mrpt::maps::CMetricMap& out) const
{
    auto* pts = dynamic_cast<mrpt::maps::CPointsMap*>(&out);
    if (!pts)
        throw std::invalid_argument(
            std::string("ParticlesLayer::renderInto: cannot draw particles into a ") +
            out.GetRuntimeClass()->className);
    auto* xyzi = dynamic_cast<mrpt::maps::CPointsMapXYZI*>(&out);
    for (const Particle& p : particles_)
    {
        if (p.weight < options_.render_min_weight) continue;
        const Eigen::Vector2d c = reference_to_current.mapPoint(p.position);
        pts->insertPoint(static_cast<float>(c.x()), static_cast<float>(c.y()));
        if (xyzi) xyzi->setPointIntensity(xyzi->size() - 1, static_cast<float>(p.weight));
    }
}

void ParticlesLayer::save(std::ostream& out) const
{
    out << "particles " << particles_.size() << '\n' << std::hexfloat;
    for (const Particle& p : particles_)
        out << p.position.x() << ' ' << p.position.y() << ' ' << p.weight << '\n';
    out << std::defaultfloat;
}

void ParticlesLayer::load(std::istream& in)
{
    constexpr const char* kWho = "ParticlesLayer::load";
    const size_t n = text_io::readHeader(in, "particles", kWho);
    std::vector<Particle> ps;
    ps.reserve(n);
    for (size_t i = 0; i < n; ++i)
    {
        Particle p{};
        p.position.x() = text_io::readNumber(in, kWho);
        p.position.y() = text_io::readNumber(in, kWho);
        p.weight = text_io::readNumber(in, kWho);
        if (!p.position.allFinite() || !(p.weight >= 0 && p.weight <= 1))
            throw std::runtime_error(std::string(kWho) + ": bad particle " + std::to_string(i));
        ps.push_back(p);
    }
    particles_ = std::move(ps);
}

}  // namespace hymm::dense
