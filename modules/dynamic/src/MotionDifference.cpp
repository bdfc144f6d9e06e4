// One differencing of a region's occupancy (thesis Sec. 6.3.1, Fig. 6.9 c-d): the
// snapshot of P(occupied) and D = |P_now - P_then|, its Gaussian low-pass and threshold.
#include "hymm/dynamic/MotionDetector.h"

#include <hymm/dense/OccupancyLayer.h>
#include <hymm/dense/geometry.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hymm::dynamic
{
size_t Difference::marked() const
{
    return static_cast<size_t>(std::count(mask.begin(), mask.end(), std::uint8_t{1}));
}

OccupancySnapshot OccupancySnapshot::take(const dense::OccupancyLayer& occ, double t)
{
    OccupancySnapshot s;
    s.assign(occ, t);
    return s;
}

void OccupancySnapshot::assign(const dense::OccupancyLayer& occ, double t_now)
{
    const auto& g = occ.grid();
    t = t_now;
    origin = g.origin();
    cell_size = g.cellSize();
    nx = g.sizeX();
    ny = g.sizeY();
    const size_t n = static_cast<size_t>(nx) * static_cast<size_t>(ny);
    p.resize(n);
    inside.resize(n);
    for (int iy = 0; iy < ny; ++iy)
        for (int ix = 0; ix < nx; ++ix)
        {
            const size_t k = static_cast<size_t>(iy) * static_cast<size_t>(nx) + static_cast<size_t>(ix);
            p[k] = static_cast<float>(dense::logistic(g.logOdds(ix, iy)));
            inside[k] = g.updatable(ix, iy) ? 1 : 0;
        }
}

bool OccupancySnapshot::sameGeometry(const OccupancySnapshot& o) const
{
    return nx == o.nx && ny == o.ny && std::abs(cell_size - o.cell_size) < 1e-12 &&
           (origin - o.origin).norm() < 1e-9;
}

Difference differenceOccupancy(const OccupancySnapshot& then, const OccupancySnapshot& now, double sigma_cells,
                               double threshold, int min_cluster_cells, int shift_tolerance_cells)
{
    Difference d;
    differenceOccupancy(then, now, sigma_cells, threshold, d, min_cluster_cells, shift_tolerance_cells);
    return d;
}

void removeSmallClusters(Difference& d, int min_cells)
{
    if (min_cells <= 1 || d.mask.empty()) return;
    // OpenCV labels the 8-connected clusters into the reused label storage (a header on
    // it: connectedComponents keeps a destination of the right size and type).
    d.cluster_labels.resize(d.mask.size());
    const cv::Mat mask(d.ny, d.nx, CV_8U, d.mask.data());
    cv::Mat labels(d.ny, d.nx, CV_32S, d.cluster_labels.data());
    const int n = cv::connectedComponents(mask, labels, 8, CV_32S);
    if (labels.ptr<int>(0) != d.cluster_labels.data())
        throw std::logic_error("removeSmallClusters: the labelling reallocated its output");
    d.cluster_sizes.assign(static_cast<size_t>(n), 0);
    for (const int l : d.cluster_labels) ++d.cluster_sizes[static_cast<size_t>(l)];
    for (size_t k = 0; k < d.mask.size(); ++k)
        if (d.mask[k] && d.cluster_sizes[static_cast<size_t>(d.cluster_labels[k])] < min_cells) d.mask[k] = 0;
}

namespace
{
/** out = the cells of `s` inside the region with P > 0.5, dilated by `cells` (a square
 *  of side 2 cells + 1: OpenCV's default 3x3 element applied `cells` times). */
void occupiedNear(const OccupancySnapshot& s, int cells, std::vector<std::uint8_t>& out)
{
    const size_t n = s.p.size();
    out.resize(n);
    for (size_t k = 0; k < n; ++k) out[k] = s.inside[k] && s.p[k] > 0.5f ? 1 : 0;
    cv::Mat m(s.ny, s.nx, CV_8U, out.data());
    cv::dilate(m, m, cv::Mat(), cv::Point(-1, -1), cells, cv::BORDER_CONSTANT, cv::Scalar(0));
    if (n > 0 && m.ptr<std::uint8_t>(0) != out.data())
        throw std::logic_error("suppressEdgeShifts: the dilation reallocated its output");
}
}  // namespace

void suppressEdgeShifts(const OccupancySnapshot& then, const OccupancySnapshot& now, int cells, Difference& d)
{
    if (cells <= 0 || d.raw.empty()) return;
    occupiedNear(then, cells, d.near_then);
    occupiedNear(now, cells, d.near_now);
    for (size_t k = 0; k < d.raw.size(); ++k)
    {
        if (d.raw[k] == 0.0f) continue;
        const bool appeared = now.p[k] > then.p[k];
        if (appeared ? d.near_then[k] : d.near_now[k]) d.raw[k] = 0.0f;
    }
}

void differenceOccupancy(const OccupancySnapshot& then, const OccupancySnapshot& now, double sigma_cells,
                         double threshold, Difference& d, int min_cluster_cells, int shift_tolerance_cells)
{
    if (!then.sameGeometry(now))
        throw std::invalid_argument("differenceOccupancy: snapshots on different grids");
    d.nx = now.nx;
    d.ny = now.ny;
    const size_t n = now.p.size();
    d.raw.assign(n, 0.0f);
    for (size_t k = 0; k < n; ++k)
        if (now.inside[k] && then.inside[k]) d.raw[k] = std::abs(now.p[k] - then.p[k]);
    suppressEdgeShifts(then, now, shift_tolerance_cells, d);
    if (sigma_cells > 0)
    {
        // Gaussian low-pass (Sec. 6.3.3, Fig. 6.9 d); kernel to +-3 sigma. Cells outside
        // the triangle are 0 (no evidence), the grid border replicates.
        // The output is written into d.filtered (a header on its storage: GaussianBlur
        // keeps a destination of the right size and type).
        d.filtered.resize(n);
        const cv::Mat src(d.ny, d.nx, CV_32F, d.raw.data());
        cv::Mat dst(d.ny, d.nx, CV_32F, d.filtered.data());
        const int half = std::max(1, static_cast<int>(std::ceil(3.0 * sigma_cells)));
        cv::GaussianBlur(src, dst, cv::Size(2 * half + 1, 2 * half + 1), sigma_cells, sigma_cells,
                         cv::BORDER_REPLICATE);
        if (n > 0 && dst.ptr<float>(0) != d.filtered.data())
            throw std::logic_error("differenceOccupancy: the low-pass reallocated its output");
    }
    else
        d.filtered = d.raw;
    d.mask.assign(n, 0);
    for (size_t k = 0; k < n; ++k)
        if (now.inside[k] && d.filtered[k] > threshold) d.mask[k] = 1;
    removeSmallClusters(d, min_cluster_cells);
}

}  // namespace hymm::dynamic
