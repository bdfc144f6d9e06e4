/**
 * @file CarParkImporter.h
 * @brief ACFR car park (Nebot / Nieto; the thesis's experimental environment) to an MRPT
 *        rawlog with odometry and raw laser scans, plus GPS and surveyed beacons.
 *
 * Inputs (original files as downloaded):
 *  - data_set.mat: `Time_VS` [s], `Velocity` [m/s], `Steering` [rad] (40 Hz);
 *    `TimeLaser` [s], `Laser` (scans x 361 ranges [m], 0.5 deg from the laser's right to
 *    its left, 81.9 = no return), `Intensity` (same shape); `TimeGPS`, `GPSLon`, `GPSLat`;
 *  - beac_juan3.mat (optional): `estbeac` (N x 2) beacon positions surveyed with
 *    kinematic GPS, in the GPS frame.
 *
 * Time base: the dataset's seconds, unchanged. Geometry as in VictoriaParkImporter: with
 * `track_laser` the odometry tracks the laser at (a, b) = (3.78, 0.5) m and the scan's
 * sensorPose is the identity; otherwise it tracks the rear-axle centre and sensorPose is
 * (a, b, 0).
 *
 * Outputs (`<name>` = Options::name): `<name>.rawlog` (CActionRobotMovement2D +
 * CObservation2DRangeScan "LASER" with intensities; beams at or beyond
 * `no_return_range_m` are invalid), `<name>_gps.tum` (phi = 0: heading unknown) and
 * `<name>_beacons.csv` (id = row of estbeac, 1-based).
 */
#pragma once

#include <hymm/core/OptionTable.h>

#include <hymm/core/UteVehicleModel.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservation.h>

#include <string>
#include <vector>

#include "hymm/datasets/ImportSummary.h"
#include "hymm/datasets/OdometryIntegrator.h"
#include "hymm/datasets/ground_truth.h"

namespace hymm::datasets
{
class MatFile;

class CarParkImporter
{
   public:
    struct Options : public mrpt::config::CLoadableOptions
    {
        std::string name = "carpark";  //!< prefix of the output files
        /** Thesis Appendix A: laser at a = 3.78, b = 0.5 [m]. */
        hymm::core::UteParams vehicle{2.83, 0.76, 3.78, 0.5};
        bool track_laser = true;          //!< odometry of the laser (true) or the rear axle
        double no_return_range_m = 81.0;  //!< ranges >= this are "no return" [m]
        double min_range_m = 0.1;         //!< ranges below are invalid [m]
        double range_std_m = 0.05;        //!< CObservation2DRangeScan::stdError [m]
        double aperture_deg = 180.0;      //!< field of view of the 361 beams [deg]
        OdometryIntegrator::Options odometry;
        GpsFilterOptions gps;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    };

    struct Inputs
    {
        std::string data_mat;     //!< data_set.mat
        std::string beacons_mat;  //!< beac_juan3.mat, or "" for none
    };

    static Inputs findInputs(const std::vector<std::string>& paths);

    explicit CarParkImporter(const Options& options) : options_(options) {}

    ImportSummary run(const Inputs& in, const std::string& out_dir) const;

    /** The laser scans of data_set.mat as CObservation2DRangeScan, sorted by time. */
    std::vector<mrpt::obs::CObservation::Ptr> readScans(const MatFile& f,
                                                        ImportSummary& summary) const;

   private:
    const Options options_;
};

}  // namespace hymm::datasets
