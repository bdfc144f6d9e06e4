/**
 * @file PotentialRegionSet.cpp
 * @brief Potential regions of Sec. 3.7.3 (see the header for the conditions and costs).
 */
#include "hymm/uif/PotentialRegionSet.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace hymm::uif
{
using hymm::ltr::BaseConditionChecker;
using hymm::ltr::TriangleFrame;
using Vertices = TriangleFrame::Vertices;

namespace
{
/** A landmark on a candidate's edge is allowed; strictly inside (by this margin in local
 *  coordinates) it would split the triangle. */
constexpr double kStrictInsideTol = -1e-9;

std::array<Eigen::Vector2d, 2> box(const Vertices& v)
{
    return {v[0].cwiseMin(v[1]).cwiseMin(v[2]), v[0].cwiseMax(v[1]).cwiseMax(v[2])};
}
}  // namespace

PotentialRegionSet::PotentialRegionSet(double search_radius_m, int max_candidate_landmarks)
    : search_radius_m_(search_radius_m), max_candidate_landmarks_(max_candidate_landmarks)
{
    if (!(search_radius_m > 0))
        throw std::invalid_argument("PotentialRegionSet: search_radius_m must be > 0");
    if (max_candidate_landmarks < 3)
        throw std::invalid_argument("PotentialRegionSet: max_candidate_landmarks must be >= 3");
}

bool PotentialRegionSet::currentVertices(
    const hymm::ekf::EkfSlam& ekf, const std::array<long, 3>& ids, Vertices& v)
{
    for (size_t k = 0; k < 3; ++k)
    {
        if (!ekf.hasLandmark(ids[k]) || ekf.landmarkBlock(ids[k]).dim != 2) return false;
        v[k] = ekf.landmarkMean(ids[k]);
    }
    return true;
}

bool PotentialRegionSet::passesGeometryAndOverlap(
    const hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition,
    const std::array<long, 3>& ids, const Vertices& v) const
{
    const BaseConditionChecker& checker = partition.checker();
    const std::array<Eigen::Matrix2d, 3> cov{
        {ekf.landmarkCov(ids[0]), ekf.landmarkCov(ids[1]), ekf.landmarkCov(ids[2])}};
    if (!checker.checkGeometry(v, cov).accepted()) return false;  // Sec. 3.5 condition 2
    const auto [lo, hi] = box(v);
    std::vector<Vertices> existing;
    for (long rid : partition.regionsInBox(lo, hi)) existing.push_back(partition.region(rid).current);
    return checker.checkOverlap(v, existing).accepted();  // Sec. 3.5 condition 3
}

size_t PotentialRegionSet::refresh(
    const hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition)
{
    size_t dropped = 0;
    for (auto it = regions_.begin(); it != regions_.end();)
    {
        Vertices v;
        const bool ok = currentVertices(ekf, it->second.vertex_ids, v) &&
                        passesGeometryAndOverlap(ekf, partition, it->second.vertex_ids, v);
        if (ok)
        {
            ++it;
            continue;
        }
        it = regions_.erase(it);
        ++dropped;
    }
    return dropped;
}

std::vector<PotentialRegionSet::Candidate> PotentialRegionSet::candidates(
    const hymm::ekf::EkfSlam& ekf, const hymm::ltr::RegionPartition& partition,
    const Eigen::Vector2d& centre) const
{
    // The k confirmed point landmarks nearest to the vehicle (O(n) over the ids).
    std::vector<std::pair<double, long>> near;
    for (long id : ekf.landmarkIds())
    {
        const auto& b = ekf.landmarkBlock(id);
        if (b.dim != 2 || !b.confirmed) continue;
        const double d = (ekf.landmarkMean(id) - centre).norm();
        if (d <= search_radius_m_) near.emplace_back(d, id);
    }
    const size_t k = std::min(near.size(), static_cast<size_t>(max_candidate_landmarks_));
    std::partial_sort(near.begin(), near.begin() + static_cast<long>(k), near.end());
    near.resize(k);

    std::vector<Candidate> out;
    for (size_t a = 0; a < k; ++a)
        for (size_t b = a + 1; b < k; ++b)
            for (size_t c = b + 1; c < k; ++c)
            {
                Candidate cand{{{near[a].second, near[b].second, near[c].second}}, {}};
                currentVertices(ekf, cand.ids, cand.v);
                if (!passesGeometryAndOverlap(ekf, partition, cand.ids, cand.v)) continue;
                const TriangleFrame f(cand.v);  // valid: the geometry check passed
                bool empty = true;
                for (size_t o = 0; o < k && empty; ++o)
                    if (o != a && o != b && o != c)
                        empty = !TriangleFrame::insideLocal(
                            f.toLocal(ekf.landmarkMean(near[o].second)), kStrictInsideTol);
                bool overlaps_potential = false;
                for (const auto& [pid, pr] : regions_)
                {
                    Vertices pv;
                    if (currentVertices(ekf, pr.vertex_ids, pv) &&
                        BaseConditionChecker::interiorsOverlap(cand.v, pv))
                        overlaps_potential = true;
                }
                if (empty && !overlaps_potential) out.push_back(std::move(cand));
            }
    return out;
}

std::vector<long> PotentialRegionSet::assign(
    const std::vector<Eigen::Vector2d>& points, const hymm::ekf::EkfSlam& ekf,
    const hymm::ltr::RegionPartition& partition, const Eigen::Vector2d& centre)
{
    std::vector<long> owner(points.size(), -1);
    size_t uncovered = points.size();
    const auto cover = [&](long pid, const TriangleFrame& f)
    {
        for (size_t i = 0; i < points.size(); ++i)
            if (owner[i] < 0 && f.contains(points[i]))
            {
                owner[i] = pid;
                --uncovered;
            }
    };
    for (const auto& [pid, pr] : regions_)
    {
        Vertices v;
        if (!currentVertices(ekf, pr.vertex_ids, v)) continue;
        if (auto f = TriangleFrame::tryCreate(v)) cover(pid, *f);
    }
    if (uncovered == 0) return owner;

    // Greedy cover of the rest: the candidate holding most uncovered points first;
    // candidates overlapping a chosen one are dropped (potential regions are disjoint).
    std::vector<Candidate> cands = candidates(ekf, partition, centre);
    while (uncovered > 0 && !cands.empty())
    {
        size_t best = 0, best_count = 0;
        for (size_t c = 0; c < cands.size(); ++c)
        {
            const TriangleFrame f(cands[c].v);
            size_t n = 0;
            for (size_t i = 0; i < points.size(); ++i)
                if (owner[i] < 0 && f.contains(points[i])) ++n;
            if (n > best_count) best = c, best_count = n;
        }
        if (best_count == 0) break;
        const Candidate chosen = cands[best];
        const long pid = next_id_++;
        regions_[pid] = PotentialRegion{pid, chosen.ids};
        cover(pid, TriangleFrame(chosen.v));
        cands.erase(std::remove_if(cands.begin(), cands.end(),
                                   [&](const Candidate& c)
                                   { return BaseConditionChecker::interiorsOverlap(c.v, chosen.v) ||
                                            c.ids == chosen.ids; }),
                    cands.end());
    }
    return owner;
}

void PotentialRegionSet::retainOnly(std::vector<long> in_use)
{
    std::sort(in_use.begin(), in_use.end());
    for (auto it = regions_.begin(); it != regions_.end();)
    {
        if (std::binary_search(in_use.begin(), in_use.end(), it->first))
            ++it;
        else
            it = regions_.erase(it);
    }
}

const PotentialRegion& PotentialRegionSet::region(long id) const
{
    const auto it = regions_.find(id);
    if (it == regions_.end())
        throw std::out_of_range("PotentialRegionSet: unknown potential region " + std::to_string(id));
    return it->second;
}

std::vector<long> PotentialRegionSet::ids() const
{
    std::vector<long> out;
    for (const auto& kv : regions_) out.push_back(kv.first);
    return out;
}

}  // namespace hymm::uif
