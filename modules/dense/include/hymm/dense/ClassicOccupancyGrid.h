/**
 * @file ClassicOccupancyGrid.h
 * @brief The classic occupancy-grid baseline (thesis Sec. 2.8.1, Fig. 4.3a, 4.5).
 *
 * One global grid over a predefined area. Each scan is inserted at the vehicle pose
 * estimated at observation time and never corrected afterwards: the cells are treated
 * as independent of the vehicle pose, which is exactly the flaw DenseSLAM removes
 * (after a loop closure the grid keeps the old, wrong wall positions). It uses the same
 * inverse sensor model and update as OccupancyLayer, so a comparison isolates the
 * effect of storing content relative to landmarks.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include "hymm/dense/LogOddsGrid.h"
#include "hymm/dense/OccupancyLayer.h"
#include "hymm/dense/ScanPoints.h"

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

namespace mrpt::serialization
{
class CArchive;
}

namespace hymm::dense
{
class ClassicOccupancyGrid
{
public:
    /** Ini section [ClassicOccupancyGrid]; unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        double x_min_m = -50, x_max_m = 50;  //!< [m] predefined map area
        double y_min_m = -50, y_max_m = 50;  //!< [m]
        double max_range_m = 25.0;           //!< [m] returns beyond are free space only

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "ClassicOccupancyGrid") const;
    };

    /** `model` supplies cell size and the inverse sensor model ([OccupancyLayer]). */
    ClassicOccupancyGrid(const Options& options, const OccupancyLayer::Options& model);

    /** Inserts a scan at the pose estimate of observation time (never revisited). */
    void insertScan(const ScanPoints& scan, const mrpt::math::TPose2D& vehicle_pose);

    double probabilityAt(const Eigen::Vector2d& p) const;
    const LogOddsGrid& grid() const { return grid_; }
    /** Saved run state (hymm-slam --save-state): every member a later step reads, bit
     *  for bit; loadState() replaces them (options come from the config). Throws
     *  std::runtime_error on a corrupt or truncated state. Source: HybridMetricMapState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);
    /** Same area and cells as a mrpt::maps::COccupancyGridMap2D. */
    void toOccupancyGridMap(mrpt::maps::COccupancyGridMap2D& out) const;

private:
    const Options options_;
    const OccupancyLayer::Options model_;
    LogOddsGrid grid_;
};

}  // namespace hymm::dense
