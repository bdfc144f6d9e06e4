/**
 * @file VirtualLandmarks.h
 * @brief Where to put virtual landmarks (thesis Sec. 3.5.1, Fig. 3.11).
 *
 * Landmarks often lie on one side of what the laser sees (trees along a road, a
 * building's walls with no landmark inside): no triangle of real landmarks can hold
 * those returns. A virtual landmark is a point placed beyond a boundary edge (a, b) of
 * the partition, carried by the filter as a state that is never observed, so that the
 * region (a, b, v) covers the returns. It is created from the vehicle pose while the
 * vehicle is highly correlated with a and b, so v is as well known relative to a and b
 * as the vehicle is (its covariance is the vehicle's, propagated, plus a small
 * definitional noise); the thesis notes that such a region is less accurate than one
 * with three real vertices, which is why real triangles are always preferred: virtual
 * ones are only proposed for returns no region holds after the partition grew.
 *
 * This file only decides WHERE: for each free edge near the vehicle whose two real
 * vertices pass the vehicle-correlation test, the returns in no region that lie on the
 * free side of the edge and project inside it are counted; if enough, the apex is put
 * on the edge's perpendicular bisector at the depth that makes the triangle hold all of
 * them (plus a margin). The pipeline adds the point to the filter (as a passive state,
 * so the feature map is untouched) and asks the partition to accept the region under
 * the usual Sec. 3.5 conditions.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include "hymm/ltr/LandmarkCovarianceView.h"
#include "hymm/ltr/RegionPartition.h"

#include <mrpt/config/CLoadableOptions.h>

#include <vector>

namespace hymm::ltr
{
/** Ini section [VirtualLandmarks]; unknown keys are errors. */
struct VirtualLandmarkOptions : public mrpt::config::CLoadableOptions
{
    bool enabled = false;
    double min_vehicle_correlation = 0.9;  //!< [0..1] of each real edge vertex with the vehicle
    int min_points = 10;          //!< returns beyond an edge needed to propose a virtual vertex
    double min_depth_m = 2.0;     //!< [m] smallest apex distance from the edge
    double max_depth_m = 20.0;    //!< [m] returns deeper than this are not considered
    double margin_m = 1.0;        //!< [m] added to the depth that holds the returns
    double search_radius_m = 25.0;  //!< [m] edges with both ends this close to the vehicle
    int max_per_frame = 2;        //!< virtual landmarks created per frame at most
    double position_std_m = 0.05;  //!< [m] definitional noise added to the propagated covariance

    /** Every ini key, declared once: loader, saver and README table come from it. */
    hymm::core::OptionTable table();
    void loadFromConfigFile(
        const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(
        mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    void validate(const std::string& section = "VirtualLandmarks") const;
};

/** A proposed virtual vertex for the free edge (a, b). */
struct VirtualLandmarkProposal
{
    long a = -1, b = -1;               //!< real vertices of the free edge
    long region = -1;                  //!< the region that owns the edge
    Eigen::Vector2d position = Eigen::Vector2d::Zero();  //!< apex (global, current estimates)
    Eigen::Vector2d edge_midpoint = Eigen::Vector2d::Zero();
    Eigen::Vector2d outward = Eigen::Vector2d::Zero();  //!< unit normal to the free side
    double side = 1;                   //!< outward = side * Rot90(b - a) / |b - a|
    double depth = 0;                  //!< [m] apex distance from the edge
    size_t points = 0;                 //!< returns the triangle holds
};

/**
 * The apex v = (a + b) / 2 + depth * side * Rot90(b - a) / |b - a| of a virtual vertex
 * on the perpendicular bisector of the edge (a, b), and its Jacobians with respect to a
 * and b. Defining v from a and b (rather than from the vehicle pose) makes the region
 * rigid with its edge: v is as correlated with a and b as the filter allows, which is
 * what the correlation condition of Sec. 3.5 asks of a base; the vehicle-correlation
 * test at creation (Sec. 3.5.1) is what keeps the points stored in it accurate.
 * Throws std::invalid_argument if a == b.
 */
Eigen::Vector2d virtualApex(
    const Eigen::Vector2d& a, const Eigen::Vector2d& b, double side, double depth,
    Eigen::Matrix2d* J_a = nullptr, Eigen::Matrix2d* J_b = nullptr);

/**
 * Proposals, most returns first, at most options.max_per_frame of them and at most one
 * per edge. `unassigned` are the global positions of returns no region holds (from
 * HybridMetricMap::insertScan). The partition's current vertices must be up to date.
 * Proposals whose triangle would contain a landmark of `view` are dropped.
 */
std::vector<VirtualLandmarkProposal> proposeVirtualLandmarks(
    const RegionPartition& partition, const LandmarkCovarianceView& view,
    const std::vector<Eigen::Vector2d>& unassigned, const VirtualLandmarkOptions& options);

}  // namespace hymm::ltr
