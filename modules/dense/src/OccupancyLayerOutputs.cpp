/**
 * @file OccupancyLayerOutputs.cpp
 * @brief The occupancy layer's outputs: occupancy.gridmap (MRPT COccupancyGridMap2D),
 *        occupancy.png and occupancy_regions.csv; its outline metrics score the centres
 *        of the occupied cells.
 */
#include "layer_outputs.h"

#include "hymm/core/output_files.h"
#include "hymm/core/serialized_file.h"
#include "hymm/dense/CHybridMetricMap.h"
#include "hymm/dense/map_images.h"
#include "hymm/dense/outline_metrics.h"

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <ostream>

namespace hymm::dense
{
namespace
{
// Occupancy layer rendered at its own cell size.
mrpt::maps::COccupancyGridMap2D renderOccupancy(const LayerOutputContext& c)
{
    mrpt::maps::COccupancyGridMap2D grid;
    c.map.renderOccupancy(c.partition, c.map.options().occupancy.cell_size_m, grid);
    return grid;
}

void writeOccupancyRegions(const LayerOutputContext& c, const std::string& file)
{
    core::AtomicTextFile f(file);
    f << "id,coarse,cell_size_m,cells,occupied,free,memory_bytes\n";
    for (const auto& r : c.map.occupancyRegionStats(kOccupiedProbability))
        f << r.id << ',' << (r.coarse ? 1 : 0) << ',' << r.cell_size_m << ',' << r.cells << ','
          << r.occupied << ',' << r.free << ',' << r.memory_bytes << '\n';
    f.commit();
}

void writeOccupancy(const LayerOutputContext& c, const std::string& d, bool png)
{
    const auto grid = renderOccupancy(c);
    // MRPT reads a cell as P(free): the file holds 1 - P(occupied), as its tools expect.
    core::writeSerializedGz(freeProbabilityGrid(grid), d + "occupancy.gridmap");
    if (png) saveOccupancyPng(grid, d + "occupancy.png", &c.partition);
    writeOccupancyRegions(c, d + "occupancy_regions.csv");
}

/** Number of occupancy regions at the coarse and at the fine cell size. Their content
 *  is compared on occupancy_regions.csv of runs with and without coarsening
 *  (benchmarks/dense_layers): a coarse cell is occupied when any fine cell it replaced
 *  was, so occupied fractions in the current cells are not comparable across sizes. */
struct CoarsenSummary
{
    size_t coarse = 0, fine = 0;
};

CoarsenSummary coarsenSummary(const LayerOutputContext& c)
{
    CoarsenSummary s;
    for (const auto& r : c.map.occupancyRegionStats(kOccupiedProbability))
        (r.coarse ? s.coarse : s.fine) += 1;
    return s;
}

std::vector<LayerCounter> occupancyCounts(const LayerOutputContext& c)
{
    const CoarsenSummary s = coarsenSummary(c);
    return {{"regions_coarse", static_cast<unsigned long>(s.coarse)},
            {"regions_fine", static_cast<unsigned long>(s.fine)}};
}

std::vector<Eigen::Vector2d> occupancyScored(const LayerOutputContext& c)
{
    return occupiedCellCentres(renderOccupancy(c), kOccupiedProbability);
}

void describeOccupancy(std::ostream& f, const LayerOutputContext& c, size_t n)
{
    const CoarsenSummary s = coarsenSummary(c);
    f << n << " cells updated, regions coarse " << s.coarse << " / fine " << s.fine;
}
}  // namespace

LayerOutputs occupancyLayerOutputs()
{
    return {writeOccupancy, occupancyCounts, occupancyScored, describeOccupancy};
}

}  // namespace hymm::dense
