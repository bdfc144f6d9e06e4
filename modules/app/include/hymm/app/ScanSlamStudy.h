/**
 * @file ScanSlamStudy.h
 * @brief Scan-SLAM (landmark_source = scan_landmarks) on a simulated run scored against
 *        the simulator's truth: path error and vehicle NEES per step, landmark pose
 *        errors before and after the loop closure, template points' distance to the true
 *        object outlines, time per step. Used by the Scan-SLAM test and the evaluation
 *        app hymm-scanslam-eval.
 *
 * A scan landmark's true pose is its template frame placed by the TRUE sensor pose of
 * the scan that created it (x_L = (x_v,true (+) s) (+) z): the template is the landmark's
 * definition, so this is where the filter's frame would be with a perfect vehicle pose.
 * The loop closure is the first frame in which a landmark created more than
 * `closure_min_age_s` earlier is updated again.
 */
#pragma once

#include <hymm/denseslam/DenseSlam.h>
#include <hymm/sim/Scenario.h>
#include <mrpt/config/CConfigFileBase.h>

#include <Eigen/Core>
#include <vector>

namespace hymm::app
{
struct ScanSlamRun
{
    struct Step
    {
        double t = 0;
        Eigen::Vector3d truth = Eigen::Vector3d::Zero();
        Eigen::Vector3d estimate = Eigen::Vector3d::Zero();
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        double nees = 0;     //!< vehicle NEES (3 DOF), NaN if the covariance is singular
        Eigen::Vector3d dead_reckoning = Eigen::Vector3d::Zero();  //!< the simulator's
        double seconds = 0;  //!< CPU time of the frame (odometry + scan), this thread
    };
    /** Landmark pose errors at one instant. */
    struct LandmarkErrors
    {
        size_t landmarks = 0;
        double rmse_xy_m = 0;     //!< position of the template frame
        double rmse_phi = 0;      //!< [rad] orientation
        double mean_nees = 0;     //!< 3-DOF NEES averaged over the landmarks
    };
    /** A converged alignment scored against the truth: z_true = (x_v,true (+) s)^-1 (+) x_L,true. */
    struct Observation
    {
        double t = 0;
        long id = -1;            //!< the landmark
        Eigen::Vector2d sensor = Eigen::Vector2d::Zero();  //!< true sensor position
        double travel_m = 0;     //!< true sensor displacement since the landmark was made
        double view_change = 0;  //!< [rad] change of the landmark-to-sensor direction since then
        double range_m = 0;      //!< true distance from the sensor to the landmark frame
        Eigen::Vector3d error = Eigen::Vector3d::Zero();  //!< z - z_true, angle wrapped
        Eigen::Vector3d pred_error = Eigen::Vector3d::Zero();  //!< z_hat - z_true
        Eigen::Matrix3d R = Eigen::Matrix3d::Zero();      //!< the covariance fused with z
        bool updated = false;    //!< fused (false: gated)
        bool wide = false;       //!< found by the wide search (ScanLandmarkMap::observeWide)
    };
    /** A fused alignment of the scan odometry ([ScanOdometry]) to its reference scan:
     *  its measurement of the vehicle relative to its pose at the reference, against the
     *  true relative pose (what cov_scale and heading_cov_scale calibrate). */
    struct OdometryAlignment
    {
        Eigen::Vector3d error = Eigen::Vector3d::Zero();  //!< measured - true, angle wrapped
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();    //!< the measurement's covariance
    };
    std::vector<Step> steps;
    std::vector<Observation> observations;  //!< every converged alignment of the run
    std::vector<OdometryAlignment> odometry_alignments;  //!< empty without [ScanOdometry]
    double duration_s = 0;          //!< simulated time of the run
    double closure_t = -1;          //!< time of the loop closure (-1: none)
    size_t closure_step = 0;        //!< index of the frame of the closure
    LandmarkErrors before_closure;  //!< at the frame before the closure (or the end)
    LandmarkErrors after_closure;   //!< at the end of the run
    double path_rmse_before_m = 0;  //!< up to the closure
    double path_rmse_after_m = 0;   //!< from the closure to the end
    double path_rmse_m = 0;         //!< the whole run
    double dead_reckoning_rmse_m = 0;  //!< the odometry alone, the whole run
    double template_outline_mean_m = 0;  //!< template points (at the final estimates) to the true outlines
    size_t template_points = 0;
    denseslam::DenseSlam::Stats stats;
    std::vector<std::pair<std::string, size_t>> counters;  //!< the scan source's counters
};

/** Runs `scenario` through DenseSlam::fromConfig(`slam_cfg`) in memory and scores it. */
ScanSlamRun runScanSlamStudy(const sim::Scenario& scenario,
                             const mrpt::config::CConfigFileBase& slam_cfg,
                             double closure_min_age_s = 60.0);

}  // namespace hymm::app
