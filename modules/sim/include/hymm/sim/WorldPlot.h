/**
 * @file WorldPlot.h
 * @brief A PNG of a simulated run: objects, landmarks, the true path and the laser
 *        returns of a subsample of scans placed with the TRUE vehicle pose (so any blur
 *        is sensor noise, not localisation error).
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "hymm/sim/World.h"

namespace hymm::sim
{
class WorldPlot
{
public:
    /** Section [WorldPlot]. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        double resolution_m = 0.1;  //!< metres per pixel (coarsened for huge worlds)
        long scan_stride = 5;       //!< plot the returns of every n-th scan
        double margin_m = 5;        //!< white border around everything drawn [m]

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();

        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                              const std::string& section) const override;
    };

    explicit WorldPlot(const Options& options);

    /** Records one frame: the true vehicle pose and, every scan_stride-th scan, the
     *  scan's valid returns (scan may be null). */
    void add(const Eigen::Vector3d& true_pose, const mrpt::obs::CObservation2DRangeScan* scan);

    /** Draws everything on a white canvas and writes it; throws if it cannot. */
    void save(const std::string& png_path, const World& world, const std::string& title) const;

    const std::vector<Vec2>& returns() const { return returns_; }

private:
    const Options options_;
    std::vector<Vec2> path_;
    std::vector<Vec2> returns_;
    size_t scans_ = 0;
};

}  // namespace hymm::sim
