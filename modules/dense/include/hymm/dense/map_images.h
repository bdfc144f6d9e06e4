/**
 * @file map_images.h
 * @brief PNG pictures of rendered dense maps (Fig. 4.3 style), optionally with the
 *        current LTR triangle edges drawn over them.
 *
 * Images have x to the right and y up (row 0 is the largest y).
 */
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CPointsMap.h>
#include <mrpt/maps/CPointsMapXYZI.h>

#include <string>
#include <vector>

#include "hymm/dense/ScalarField.h"
#include "hymm/ltr/RegionPartition.h"

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

/** Points coloured by their intensity (OpenCV JET over [v_min, v_max], clamped) on
 *  white, at `resolution_m` per pixel over the points' bounding box (and the
 *  triangles', drawn in red, if given) plus `margin_m`. Points are drawn in increasing
 *  intensity, so high values stay visible where points overlap. Used for the particle
 *  layer with the weight P(occupied) as intensity (Fig. 4.10). */
void savePointsByValuePng(const mrpt::maps::CPointsMapXYZI& points, const std::string& path,
                          double resolution_m, double v_min, double v_max,
                          const hymm::ltr::RegionPartition* triangles = nullptr,
                          double margin_m = 1.0);

/** Closed polylines (blue, e.g. the SOG 1-sigma ellipses of Fig. 4.13) on white at
 *  `resolution_m` per pixel over their bounding box (and the triangles', drawn in red,
 *  if given) plus `margin_m`. */
void savePolylinesPng(const std::vector<std::vector<Eigen::Vector2d>>& polylines,
                      const std::string& path, double resolution_m,
                      const hymm::ltr::RegionPartition* triangles = nullptr, double margin_m = 1.0);

/** Colour map (OpenCV JET) of `field` with values clamped to [v_min, v_max], NaN cells
 *  white; optional triangle edges (red) and closed polylines (white, e.g. the SOG
 *  1-sigma ellipses). One pixel per cell. Used for the SOG surface (Fig. 4.12 b) and
 *  property means / stds. */
void saveScalarFieldPng(
    const ScalarField& field, const std::string& path, double v_min, double v_max,
    const hymm::ltr::RegionPartition* triangles = nullptr,
    const std::vector<std::vector<Eigen::Vector2d>>* polylines = nullptr);

}  // namespace hymm::dense
