/**
 * @file ConsistencyStudy.h
 * @brief Monte Carlo consistency check of the whole pipeline against simulator ground
 *        truth: N runs of a scenario with different noise seeds, each processed by
 *        DenseSlam, and the run-averaged NEES compared with its chi-square band
 *        (Bar-Shalom's average NEES test, thesis 2.9's "the filter is consistent").
 *
 * Vehicle: at every step the NEES (3 DOF) is averaged over the runs and tested against
 * [chi2(0.025, 3N)/N, chi2(0.975, 3N)/N]. Landmarks: at the end, each true landmark's
 * NEES (2 DOF) is averaged over the runs in which it was mapped, and tested likewise.
 */
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <string>
#include <vector>

namespace hymm::app
{
struct ConsistencyStudy
{
    std::string scenario_ini;   //!< simulator scenario (configs/sim/*.ini)
    std::string slam_ini;       //!< pipeline configuration ([DenseSlam], [EkfSlam], ...)
    std::vector<long> seeds;    //!< one run per noise seed
    long laps = 0;              //!< > 0 overrides the scenario's number of laps
    std::string work_dir;       //!< rawlogs and ground truth of every run go here
    double confidence = 0.95;   //!< two-sided probability of the NEES band

    struct Result
    {
        size_t runs = 0;
        size_t steps = 0;                      //!< steps present in every run
        std::vector<double> vehicle_nees;      //!< run-averaged, per step
        double vehicle_band_lower = 0, vehicle_band_upper = 0;
        double vehicle_fraction_inside = 0;    //!< of the steps
        double vehicle_nees_mean = 0;          //!< over steps of the averaged NEES
        std::vector<double> landmark_nees;     //!< run-averaged, per true landmark
        double landmark_band_lower = 0, landmark_band_upper = 0;
        double landmark_fraction_inside = 0;
        std::vector<double> final_position_error;  //!< [m] per run, last step
        std::vector<double> path_rmse;             //!< [m] per run
        std::vector<double> landmark_mean_error;   //!< [m] per run
        /** Per run, with [HighLevelLandmarks] on (else empty): HLLs accepted,
         *  initialised in the filter, and their updates. */
        std::vector<double> hll_proposed, hll_accepted, hll_initialised, hll_updated;
        std::vector<double> vehicle_nees_run_mean;  //!< per run: mean NEES over its steps
    };

    /** Runs the study; throws on bad configuration or if runs have different lengths. */
    Result run() const;
};

}  // namespace hymm::app
