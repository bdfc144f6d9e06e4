/**
 * @file DataAssociation.h
 * @brief Range-bearing data association on a prepared problem: individual chi-square
 *        gate, nearest neighbour on the normalised distance (thesis Eq. 2.58-2.60) and
 *        joint compatibility branch and bound (JCBB, Neira & Tardos 2001; thesis
 *        "Batch Data Association Methods", section 2.4).
 *
 * The filter prepares the problem: the observations with their noise, the predicted
 * observation h_j of every candidate landmark and the joint covariance C = H P H^T of
 * those predictions (cross terms included, as they make JCBB work: a common vehicle
 * error shifts every prediction together). This keeps the algorithms independent of
 * the state layout and testable on synthetic problems.
 */
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace hymm::ekf
{
enum class AssociationMethod
{
    NearestNeighbour,  //!< greedy NN on Eq. 2.60, one observation per landmark
    JCBB               //!< joint compatibility branch and bound
};

/** Observations z_i = (range, bearing) with noise R_i, and k candidate predictions. */
struct AssociationProblem
{
    std::vector<Eigen::Vector2d> z;
    std::vector<Eigen::Matrix2d> R;
    std::vector<Eigen::Vector2d> h;  //!< predicted observation of each candidate
    Eigen::MatrixXd C;               //!< 2k x 2k: H P H^T of the candidates (no R)
};

struct AssociationResult
{
    std::vector<int> assignment;  //!< per observation: candidate index or -1
    /** m x k individual normalised innovation squared (Eq. 2.58); +inf where the
     *  2x2 innovation covariance is not positive definite. */
    Eigen::MatrixXd d2;
    double joint_nis = 0.0;      //!< joint NIS of the chosen hypothesis
    size_t jcbb_nodes = 0;       //!< interpretation-tree nodes visited (JCBB)
    bool jcbb_truncated = false; //!< node budget hit: best hypothesis found so far
};

/** z - h with the bearing difference wrapped to (-pi, pi]. */
Eigen::Vector2d rangeBearingInnovation(const Eigen::Vector2d& z, const Eigen::Vector2d& h);

/**
 * Associates the observations with the candidates. A pairing is individually
 * compatible when d2 < chi2inv(gate_prob, 2). JCBB additionally requires the joint
 * NIS of the hypothesis to be below chi2inv(gate_prob, 2 * pairings), maximises the
 * number of pairings and, among equally large hypotheses found, minimises the joint
 * NIS; it stops exploring after `jcbb_max_nodes` nodes (0: no limit).
 */
AssociationResult associate(
    const AssociationProblem& problem, AssociationMethod method, double gate_prob,
    size_t jcbb_max_nodes = 0);

}  // namespace hymm::ekf
