/**
 * @file PointsLayerOutputs.cpp
 * @brief The points layer's outputs: points.bin (MRPT CSimplePointsMap), points.txt,
 *        points.png; its outline metrics score every point.
 */
#include "layer_outputs.h"

#include "hymm/core/output_files.h"
#include "hymm/core/serialized_file.h"
#include "hymm/dense/HybridMetricMap.h"
#include "hymm/dense/map_images.h"
#include "hymm/dense/outline_metrics.h"

#include <mrpt/maps/CSimplePointsMap.h>

#include <algorithm>
#include <cstdio>
#include <ostream>

namespace hymm::dense
{
namespace
{
mrpt::maps::CSimplePointsMap renderPoints(const LayerOutputContext& c)
{
    mrpt::maps::CSimplePointsMap pts;
    c.map.renderPoints(c.partition, pts);
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

void writePoints(const LayerOutputContext& c, const std::string& d, bool png)
{
    const auto pts = renderPoints(c);
    core::writeSerializedGz(pts, d + "points.bin");
    writePointsText(pts, d + "points.txt");
    if (png) savePointsPng(pts, d + "points.png", kPointsPngResolution, &c.partition);
}

std::vector<Eigen::Vector2d> pointsScored(const LayerOutputContext& c)
{
    return pointsOf(renderPoints(c));
}

void describePoints(std::ostream& f, const LayerOutputContext&, size_t n) { f << n << " points"; }
}  // namespace

LayerOutputs pointsLayerOutputs() { return {writePoints, nullptr, pointsScored, describePoints}; }

}  // namespace hymm::dense
