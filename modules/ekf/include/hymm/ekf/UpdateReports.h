/**
 * @file UpdateReports.h
 * @brief The observations EkfSlam takes and what its updates report (EkfSlam.h).
 */
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

namespace hymm::ekf
{
/** One range-bearing observation of a point landmark, in the sensor frame. */
struct RangeBearingObs
{
    Eigen::Vector2d z = Eigen::Vector2d::Zero();  //!< (range [m], bearing [rad])
    Eigen::Matrix2d R = Eigen::Matrix2d::Identity();  //!< noise covariance, must be PD
    long id = -1;  //!< >= 0: known association (landmark id); -1: associate by gating
};

/** What updateRangeBearing() did with each observation. Every observation is counted in
 *  exactly one of associated / created / rejected_gate / ambiguous / rejected_numeric /
 *  rejected_invalid. */
struct UpdateReport
{
    size_t associated = 0;        //!< used to update an existing landmark
    size_t created = 0;           //!< started a new (tentative) landmark
    /** Inside the association gate of some landmark but not paired (lost a NN conflict
     *  or excluded by JCBB's joint test), a known id of a block that is not a point, or
     *  a known-id observation outside the known_id_gate_prob gate. */
    size_t rejected_gate = 0;
    size_t ambiguous = 0;         //!< outside the association gate of every landmark but
                                  //!< inside the creation gate of one: discarded
    size_t rejected_numeric = 0;  //!< innovation covariance not PD: update skipped
    size_t rejected_invalid = 0;  //!< NaN/inf z or R, R not PD, negative range: skipped
    size_t pruned = 0;            //!< tentative landmarks removed at the end of the step
    size_t jcbb_nodes = 0;        //!< interpretation-tree nodes explored (JCBB only)
    std::vector<long> assigned_ids;  //!< per observation: landmark id updated/created, or -1
    std::string rejection_reason;    //!< why an update was skipped (empty if none)
};

/** Outcome of one pose-landmark observation (EkfSlamPoseLandmarks.cpp). */
struct PoseUpdateReport
{
    enum class Outcome
    {
        updated,
        gated,    //!< NIS beyond the gate (thesis 5.5): not used
        numeric,  //!< innovation covariance not PD or non-finite gain: skipped
        invalid   //!< NaN/inf z or R, or R not PD: skipped
    };
    Outcome outcome = Outcome::invalid;
    double nis = 0;  //!< normalised innovation squared (3 DOF), at the prior
    int iterations = 0;  //!< relinearisations done (iterated update; 0 for the EKF)
};

}  // namespace hymm::ekf
