/**
 * @file SogLayerCap.cpp
 * @brief SogLayer's bound on the components of a region (`max_mean_per_cell`): the
 *        closest pairs are merged into one Gaussian with their mean and covariance
 *        (SogLayer.h, revisits).
 */
#include "hymm/dense/SogLayer.h"

#include "hymm/dense/geometry.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace hymm::dense
{
namespace
{
/** (squared distance, i, j), i < j: a component and its nearest neighbour. */
using Pair = std::tuple<double, size_t, size_t>;

/** Every component's nearest neighbour within `radius` (hash grid of that cell), each
 *  pair once, closest first. */
std::vector<Pair> closestPairs(const std::vector<SogLayer::Gaussian>& gs, double radius)
{
    std::unordered_map<std::int64_t, std::vector<size_t>> index;
    for (size_t i = 0; i < gs.size(); ++i) index[pointCellKey(gs[i].mean, radius)].push_back(i);
    std::vector<Pair> pairs;
    for (size_t i = 0; i < gs.size(); ++i)
    {
        size_t best = i;
        double best_d2 = radius * radius;
        for (std::int64_t dx = -1; dx <= 1; ++dx)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
            {
                const auto it = index.find(pointCellKey(gs[i].mean, radius, dx, dy));
                if (it == index.end()) continue;
                for (const size_t j : it->second)
                    if (const double d2 = (gs[j].mean - gs[i].mean).squaredNorm(); j != i && d2 < best_d2)
                    {
                        best_d2 = d2;
                        best = j;
                    }
            }
        if (best != i) pairs.emplace_back(best_d2, std::min(i, best), std::max(i, best));
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    return pairs;
}
/** Square cells of side `cell` holding a mean: the area the components cover. */
size_t occupiedCells(const std::vector<SogLayer::Gaussian>& gs, double cell)
{
    std::unordered_set<std::int64_t> cells;
    for (const SogLayer::Gaussian& g : gs) cells.insert(pointCellKey(g.mean, cell));
    return cells.size();
}
}  // namespace

SogLayer::Gaussian mergeMoments(const SogLayer::Gaussian& a, const SogLayer::Gaussian& b)
{
    // The map draws every Gaussian with peak 1 (Sec. 4.3.1, Fig. 4.11): Gaussian i is
    // 2 pi sqrt|P_i| g(x; m_i, P_i), so its weight in the drawn surface is sqrt|P_i|.
    const double wa = std::sqrt(std::max(0.0, a.cov.determinant()));
    const double wb = std::sqrt(std::max(0.0, b.cov.determinant()));
    const double fa = wa + wb > 0 ? wa / (wa + wb) : 0.5;
    const double fb = 1.0 - fa;
    SogLayer::Gaussian g;
    g.mean = fa * a.mean + fb * b.mean;
    const Eigen::Vector2d da = a.mean - g.mean, db = b.mean - g.mean;
    // Second moment of the pair about the new mean: a sum of PSD terms, so PSD.
    g.cov = fa * (a.cov + da * da.transpose()) + fb * (b.cov + db * db.transpose());
    g.cov(1, 0) = g.cov(0, 1);
    return g;
}

void SogLayer::capComponents()
{
    if (options_.max_mean_per_cell <= 0) return;
    const double cell = options_.d_min_m;
    double radius = cell;
    for (;;)
    {
        // The bound follows the area the components cover, not the number of visits.
        const auto limit = static_cast<size_t>(std::floor(options_.max_mean_per_cell *
                                                          static_cast<double>(occupiedCells(gaussians_, cell))));
        if (gaussians_.size() <= std::max<size_t>(limit, 1)) return;
        size_t excess = gaussians_.size() - std::max<size_t>(limit, 1);
        // The closest pairs first, each component in one merge per pass: the first pass
        // merges the closest pair of the region, as merging one pair at a time would,
        // and a region at its bound (a few births per scan) needs one pass.
        std::vector<char> touched(gaussians_.size(), 0), gone(gaussians_.size(), 0);
        for (const auto& [d2, i, j] : closestPairs(gaussians_, radius))
        {
            if (excess == 0) break;
            if (touched[i] || touched[j]) continue;
            gaussians_[i] = mergeMoments(gaussians_[i], gaussians_[j]);  // the older slot: birth order kept
            touched[i] = touched[j] = gone[j] = 1;
            --excess;
        }
        const size_t before = gaussians_.size();
        size_t out = 0;
        for (size_t i = 0; i < before; ++i)
            if (!gone[i]) gaussians_[out++] = gaussians_[i];
        gaussians_.resize(out);
        // No pair within the radius (components far apart): look further.
        if (out == before) radius *= 2;
    }
}

}  // namespace hymm::dense
