/**
 * @file map_images.h
 * @brief PNG pictures of rendered dense maps (Fig. 4.3 style), optionally with the
 *        current LTR triangle edges drawn over them.
 *
 * Images have x to the right and y up (row 0 is the largest y).
 */
#pragma once

#include "hymm/ltr/RegionPartition.h"

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CPointsMap.h>

#include <string>

namespace hymm::dense
{
/** One pixel per cell, grey = 255 (1 - P(occupied)). Throws std::runtime_error if the
 *  file cannot be written. */
void saveOccupancyPng(
    const mrpt::maps::COccupancyGridMap2D& grid, const std::string& path,
    const hymm::ltr::RegionPartition* triangles = nullptr);

/** Black dots on white at `resolution_m` per pixel over the points' bounding box
 *  (and the triangles', if given) plus `margin_m`. */
void savePointsPng(
    const mrpt::maps::CPointsMap& points, const std::string& path, double resolution_m,
    const hymm::ltr::RegionPartition* triangles = nullptr, double margin_m = 1.0);

}  // namespace hymm::dense
