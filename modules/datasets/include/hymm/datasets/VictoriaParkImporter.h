/**
 * @file VictoriaParkImporter.h
 * @brief Victoria Park (Guivant & Nebot, ACFR) to an MRPT rawlog with odometry and tree
 *        detections, plus the GPS as ground truth.
 *
 * Inputs (original files as downloaded):
 *  - aa3_dr.mat: `time` [ms], `speed` [m/s] (encoder on the back-left wheel), `steering`
 *    [rad], 40 Hz;
 *  - measurements.dat (ACFR ASCII release, RFS-SLAM copy): one tree detection per line,
 *    "t range bearing diameter"; t [s] on the base (.mat time / 1000 - 20.967 s); bearing
 *    0..pi from the laser's right; lines with the same t form one scan;
 *  - aa3_gpsx.mat (optional): `timeGps` [ms], `Lo_m`, `La_m` [local m].
 *
 * Time base: the rawlog uses the .mat clock in seconds (time_ms / 1000); detections are
 * shifted by `detections_time_offset_s` (20.967 s) onto it.
 *
 * Geometry: with `track_laser` (default) the odometry tracks the laser at (a, b) from
 * the rear-axle centre, so the robot frame *is* the laser frame and each observation's
 * sensorLocationOnRobot is the identity. Otherwise the odometry tracks the rear-axle
 * centre (a = b = 0 in the model) and sensorLocationOnRobot = (a, b, 0).
 * Bearing: MRPT's yaw is counter-clockwise from the sensor's forward axis; the file's
 * bearing is counter-clockwise from the laser's right (-y), so yaw = bearing - pi/2.
 *
 * Outputs in the output folder (`<name>` = Options::name):
 *  - `<name>.rawlog`: one frame per scan with detections: CActionRobotMovement2D + a
 *    CObservationBearingRange (sensorLabel "TREES", landmarkID -1: no IDs);
 *  - `<name>_tree_diameters.csv`: the trunk diameters, which CObservationBearingRange
 *    cannot hold: "frame,t,index,range_m,yaw_rad,diameter_m", `index` = position in
 *    sensedData of that frame;
 *  - `<name>_gps.tum`: the filtered GPS fixes (phi = 0: heading unknown).
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
class VictoriaParkImporter
{
   public:
    struct Options : public mrpt::config::CLoadableOptions
    {
        std::string name = "victoria_park";  //!< prefix of the output files
        /** Vehicle geometry [m]. The laser sits at a = 3.78, b = 0.5 (thesis App. A, the
         *  UTE that recorded the data); info.txt's a = 0.95 makes trunk detections smear
         *  in every turn (docs/results.md). */
        hymm::core::UteParams vehicle{2.83, 0.76, 3.78, 0.5};
        bool track_laser = true;  //!< odometry of the laser (true) or of the rear axle
        double detections_time_offset_s = 20.967;  //!< rawlog t = detections t + this [s]
        double min_range_m = 0.5;    //!< detections closer are dropped [m]
        double max_range_m = 80.0;   //!< detections farther are dropped (laser limit) [m]
        double std_range_m = 0.5;    //!< range noise written to the observations [m]
        double std_bearing_deg = 1.0;  //!< bearing noise written to the observations [deg]
        OdometryIntegrator::Options odometry;
        GpsFilterOptions gps;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        /** Loads the section; unknown keys and out-of-range values throw. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    };

    struct Inputs
    {
        std::string dr_mat;      //!< aa3_dr.mat
        std::string detections;  //!< measurements.dat
        std::string gps_mat;     //!< aa3_gpsx.mat, or "" for none
    };

    /** Finds aa3_dr.mat, measurements.dat and (optionally) aa3_gpsx.mat among `paths`
     *  (files or folders). Throws if a required file is missing. */
    static Inputs findInputs(const std::vector<std::string>& paths);

    explicit VictoriaParkImporter(const Options& options) : options_(options) {}

    /** Converts; writes the outputs listed above into `out_dir` (created if needed). */
    ImportSummary run(const Inputs& in, const std::string& out_dir) const;

    /** aa3_dr.mat as control samples (t [s] on the rawlog base, speed, steering). */
    static std::vector<OdometryIntegrator::ControlSample> readDeadReckoning(
        const std::string& path);

    /** aa3_gpsx.mat as unfiltered poses (t [s] on the rawlog base, x, y, phi = 0). */
    static std::vector<hymm::io::StampedPose2D> readGps(const std::string& path);

    /** measurements.dat as observations (one per scan, rawlog time base), sorted by time;
     *  `diameters[k]` holds the diameters of the measurements of observation k. */
    std::vector<mrpt::obs::CObservation::Ptr> readDetections(
        const std::string& path, ImportSummary& summary,
        std::vector<std::vector<double>>& diameters) const;

   private:
    const Options options_;
};

}  // namespace hymm::datasets
