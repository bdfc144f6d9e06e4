/**
 * @file single_pass_figure.h
 * @brief PNG of one single-pass dense map for the delayed-store evaluation: the true
 *        outlines, the outline samples the laser saw but the map does not cover (the
 *        holes), the map points (direct and fused from the delayed store in two colours)
 *        and the LTR triangles.
 */
#pragma once

#include <hymm/dense/outline_metrics.h>
#include <hymm/ltr/TriangleFrame.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace hymm::bench
{
struct SinglePassFigure
{
    std::string title;
    std::vector<dense::Polygon> outlines;  //!< true object outlines (all are framed)
    std::vector<Eigen::Vector2d> true_path;
    std::vector<Eigen::Vector2d> direct_points;           //!< inserted while a region covered them
    std::vector<Eigen::Vector2d> fused_points;            //!< fused later from the delayed store
    std::vector<Eigen::Vector2d> holes;                   //!< seen outline samples not covered
    std::vector<ltr::TriangleFrame::Vertices> triangles;  //!< the LTRs as drawn
    double resolution_m = 0.1;                            //!< [m / pixel]
    double margin_m = 3.0;

    /** Writes the PNG; throws std::runtime_error if it cannot. */
    void save(const std::string& path) const;
};

}  // namespace hymm::bench
