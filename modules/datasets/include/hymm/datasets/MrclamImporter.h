/**
 * @file MrclamImporter.h
 * @brief UTIAS MRCLAM (Leung et al., IJRR 2011) robot log to an MRPT rawlog with
 *        odometry and identified landmark measurements, plus Vicon ground truth.
 *
 * Inputs (one dataset folder, e.g. MRCLAM_Dataset1, or the files themselves):
 *  - Robot<r>_Odometry.dat: "t v omega" (t [s], v [m/s], omega [rad/s]);
 *  - Robot<r>_Measurement.dat: "t barcode range bearing" (range [m], bearing [rad],
 *    counter-clockwise from the robot's forward axis: MRPT's yaw already);
 *  - Barcodes.dat: "subject barcode"; Landmark_Groundtruth.dat: "subject x y sx sy";
 *  - Robot<r>_Groundtruth.dat: "t x y theta" (Vicon).
 *
 * Measurements are mapped barcode -> subject number and written with landmarkID =
 * subject. Subjects 1..`num_robots` are the robots themselves: those measurements are
 * dropped ("robot_barcode"), as are barcodes not in Barcodes.dat ("unknown_barcode").
 * Measurements with the same time form one observation. The time base is the files'.
 * Quirk: times are printed with 5 significant digits; odometry and ground-truth times
 * are rebuilt from their fixed period (see Options::sample_period_s), measurement times
 * cannot be and keep a 0.1 s resolution after 1000 s.
 *
 * Outputs (`<name>` = Options::name, default "mrclam_robot<r>"): `<name>.rawlog`
 * (CActionRobotMovement2D from the unicycle model + CObservationBearingRange
 * "LANDMARKS", sensor at the robot origin), `<name>_groundtruth.tum` (Vicon poses) and
 * `<name>_landmarks.csv` ("id,x,y,std_x,std_y", id = subject).
 */
#pragma once

#include <hymm/core/OptionTable.h>

#include <hymm/io/trajectory_io.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservation.h>

#include <map>
#include <string>
#include <vector>

#include "hymm/datasets/ImportSummary.h"
#include "hymm/datasets/OdometryIntegrator.h"

namespace hymm::datasets
{
class MrclamImporter
{
   public:
    struct Options : public mrpt::config::CLoadableOptions
    {
        std::string name;       //!< prefix of the output files ("" = "mrclam_robot<r>")
        int robot = 1;          //!< which robot's log to convert (1..num_robots)
        int num_robots = 5;     //!< subjects 1..num_robots are robots, not landmarks
        /** Period of the resampled odometry and ground-truth files [s] (0: use the
         *  printed times). The files print times with 5 significant digits, so from
         *  1000 s on five 50 Hz samples share one printed time; with a period the
         *  times are rebuilt as t_first + i * period when they agree with the printed
         *  ones within the printing resolution. */
        double sample_period_s = 0.02;
        double max_range_m = 10.0;     //!< measurements farther are dropped [m]
        double std_range_m = 0.1;      //!< range noise written to the observations [m]
        double std_bearing_deg = 2.0;  //!< bearing noise written to the observations [deg]
        /** Corrections of Barcodes.dat, "barcode:listed:actual" (space separated):
         *  where the file maps `barcode` to subject `listed`, subject `actual` is used
         *  instead; a file that maps the barcode otherwise is left alone, so the key is
         *  safe for every dataset folder. */
        struct BarcodeFix
        {
            int barcode = 0, listed = 0, actual = 0;
        };
        std::vector<BarcodeFix> barcode_fixes;
        OdometryIntegrator::Options odometry;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    };

    struct Inputs
    {
        std::string odometry, measurements, barcodes, landmarks, groundtruth;
    };

    /** Finds the files of robot `robot` among `paths`; landmarks and ground truth are
     *  optional (""), the other three are required. */
    static Inputs findInputs(const std::vector<std::string>& paths, int robot);

    explicit MrclamImporter(const Options& options);

    ImportSummary run(const Inputs& in, const std::string& out_dir) const;

    /** Barcodes.dat as barcode -> subject. Throws on a duplicated barcode. */
    static std::map<int, int> readBarcodes(const std::string& path);

    /** readBarcodes with Options::barcode_fixes applied (each applied fix counted as
     *  repaired "barcode_subject_fix"). */
    std::map<int, int> barcodeMap(const std::string& path, ImportSummary& summary) const;

    /** Robot<r>_Odometry.dat as (v, omega) samples: times rebuilt from
     *  `sample_period_s`, then OdometryIntegrator::sanitize (skips counted). */
    std::vector<OdometryIntegrator::ControlSample> readOdometry(const std::string& path,
                                                                ImportSummary& summary) const;

    /** Robot<r>_Groundtruth.dat (Vicon): times rebuilt from `sample_period_s`; rows with
     *  a non-finite value ("groundtruth_nan") or a time not after the last kept one
     *  ("groundtruth_non_monotonic") are skipped. Headings wrapped to (-pi, pi]. */
    std::vector<hymm::io::StampedPose2D> readGroundTruth(const std::string& path,
                                                           ImportSummary& summary) const;

    /** Landmark_Groundtruth.dat as records (id = subject, extra = {std_x, std_y}). */
    static std::vector<hymm::io::LandmarkRecord> readLandmarks(const std::string& path,
                                                                 ImportSummary& summary);

    /** Robot<r>_Measurement.dat as observations (one per time stamp), sorted by time. */
    std::vector<mrpt::obs::CObservation::Ptr> readMeasurements(
        const std::string& path, const std::map<int, int>& barcode_to_subject,
        ImportSummary& summary) const;

   private:
    const Options options_;
};

}  // namespace hymm::datasets
