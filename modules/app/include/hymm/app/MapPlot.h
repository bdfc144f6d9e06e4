/**
 * @file MapPlot.h
 * @brief PNG figure of a feature map: estimated path and landmarks with their
 *        n-sigma uncertainty ellipses, over the ground truth when it is known
 *        (the layout of thesis Fig. 2.8).
 */
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace hymm::app
{
struct MapPlot
{
    struct Landmark
    {
        Eigen::Vector2d mean = Eigen::Vector2d::Zero();
        Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    };
    std::vector<Eigen::Vector2d> estimated_path;
    std::vector<Eigen::Vector2d> true_path;
    std::vector<Landmark> estimated_landmarks;
    std::vector<Eigen::Vector2d> true_landmarks;
    /** A Scan-SLAM landmark: its frame (x, y, phi) with covariance and its template
     *  points placed at the frame's estimate (drawn green, with the frame's axes). */
    struct PoseLandmark
    {
        Eigen::Vector3d pose = Eigen::Vector3d::Zero();
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        std::vector<Eigen::Vector2d> points;  //!< global
    };
    std::vector<PoseLandmark> pose_landmarks;
    double axis_length = 2.0;  //!< [m] drawn length of a pose landmark's x and y axes
    std::vector<Eigen::Vector2d> dense_points;  //!< rendered dense returns (drawn first, black)
    double sigma_scale = 3.0;      //!< ellipses at this many standard deviations
    double pixels_per_metre = 8;   //!< scale, reduced if the image would exceed max_side
    int max_side = 2400;           //!< largest image side [px]
};

/** Writes the figure as a PNG; throws if there is nothing to draw or the file cannot
 *  be written. Legend: grey = truth, blue = estimate, red = n-sigma ellipses. */
void writeMapPng(const MapPlot& plot, const std::string& path);

}  // namespace hymm::app
