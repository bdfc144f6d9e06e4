#include "scan_beams.h"

#include <algorithm>
#include <cmath>

namespace hymm::extract::internal
{
std::vector<Beam> classifyBeams(
    const mrpt::obs::CObservation2DRangeScan& scan, double min_range, double max_range,
    BeamCounts& counts)
{
    const size_t n = scan.getScanSize();
    const double r_max = std::min<double>(max_range, scan.maxRange);
    counts = BeamCounts{};
    counts.total = n;
    std::vector<Beam> beams(n);
    for (size_t i = 0; i < n; ++i)
    {
        const double r = scan.getScanRange(i);
        if (!scan.getScanRangeValidity(i))
        {
            ++counts.invalid;
            continue;
        }
        if (!std::isfinite(r))
        {
            ++counts.not_finite;
            continue;
        }
        if (r < 0 || r < min_range || r >= r_max)
        {
            ++counts.out_of_range;
            continue;
        }
        Beam& b = beams[i];
        b.usable = true;
        b.range = r;
        b.angle = scan.getScanAngle(i);
        b.point = Eigen::Vector2d(r * std::cos(b.angle), r * std::sin(b.angle));
        ++counts.used;
    }
    return beams;
}

std::vector<Cluster> clusterBeams(
    const std::vector<Beam>& beams, double range_jump, const std::function<bool(size_t)>& accept)
{
    std::vector<Cluster> out;
    bool open = false;
    Cluster cur;
    for (size_t i = 0; i < beams.size(); ++i)
    {
        const bool member = beams[i].usable && accept(i);
        if (!member)
        {
            if (open) out.push_back(cur);
            open = false;
            continue;
        }
        if (open && std::abs(beams[i].range - beams[i - 1].range) <= range_jump)
        {
            cur.last = i;
            continue;
        }
        if (open) out.push_back(cur);
        cur = Cluster{i, i};
        open = true;
    }
    if (open) out.push_back(cur);
    return out;
}

std::vector<Eigen::Vector2d> clusterPoints(const std::vector<Beam>& beams, const Cluster& c)
{
    std::vector<Eigen::Vector2d> pts;
    pts.reserve(c.size());
    for (size_t i = c.first; i <= c.last; ++i) pts.push_back(beams[i].point);
    return pts;
}

double beamSpacing(const mrpt::obs::CObservation2DRangeScan& scan)
{
    const size_t n = scan.getScanSize();
    if (n < 2) return 0;
    return static_cast<double>(scan.aperture) / static_cast<double>(n - 1);
}

}  // namespace hymm::extract::internal
