/**
 * @file PassiveStates.h
 * @brief Passive states with Unidirectional Information Flow (thesis 3.7.1, Example 3.3,
 *        Fig. 3.14): state blocks that receive information from the active EKF states
 *        through their cross-covariance but never give any back.
 *
 * Stored per passive block p: its mean x_p, its own covariance P_pp and the
 * cross-covariance P_pa with every active state. Passive-passive cross terms are never
 * stored: nothing in the filter reads them, since passive states are never observed and
 * never enter the motion model. The storage is therefore N_p x n_a + sum(d_p^2) numbers
 * instead of (N_a + N_p)^2 (Example 3.3).
 *
 * The filter (EkfSlam) owns one PassiveStates and drives it: it passes the same F, gains
 * and augmentation Jacobians it applies to the active states. The active states never
 * read anything from here, so they are bitwise identical with or without passive states.
 */
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <unordered_map>
#include <vector>

namespace mrpt::serialization
{
class CArchive;
}

namespace hymm::ekf
{
class PassiveStates
{
public:
    /** Adds a block; `cross` is dim x n_active (cov(x_p, x_active)). Throws on a used or
     *  negative id, size mismatches, or a non-symmetric / non-finite covariance. */
    void add(long id, const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov,
             const Eigen::MatrixXd& cross, size_t n_active);
    /** Throws std::out_of_range if unknown. */
    void remove(long id);

    bool has(long id) const { return index_.count(id) != 0; }
    size_t numBlocks() const { return blocks_.size(); }
    size_t totalDim() const { return static_cast<size_t>(mean_.size()); }
    std::vector<long> ids() const;

    Eigen::VectorXd mean(long id) const;
    Eigen::MatrixXd cov(long id) const;
    /** cov(x_p, x_active): dim x n_active. */
    Eigen::MatrixXd crossCov(long id) const;
    /** Columns [first, first + cols) of crossCov(id), without copying the whole row
     *  block (e.g. the cross-covariance with one landmark or the vehicle). */
    Eigen::MatrixXd crossCov(long id, size_t first, int cols) const;
    /** Number of covariance entries stored (N_p * n_active + sum of d_p^2). */
    size_t storedCovarianceEntries() const;

    // ---- Propagation, called by the filter with what it applies to the active states ----

    /** Prediction (Eq. 2.36 applied to the cross terms): P_pv <- P_pv F^T. */
    void predictVehicle(const Eigen::Matrix3d& F);
    /** The same when the new pose also depends on the 1-DOF active state at `param`
     *  through G: P_pv <- P_pv F^T + P_p,param G^T. */
    void predictVehicle(const Eigen::Matrix3d& F, Eigen::Index param, const Eigen::Vector3d& G);
    /** Cross-covariance columns [to, to + dim) <- [from, from + dim) (an active block
     *  set to a copy of another). */
    void copyActiveColumns(size_t from, size_t to, size_t dim);
    /** Cross-covariance with the active states, all passive rows stacked (N_p x n_a). */
    const Eigen::MatrixXd& crossAll() const { return cross_; }
    /**
     * Kalman update with the active gain factor W_a = P_aa H^T L^-T (n_a x M), the
     * passive one W_p = P_pa H^T L^-T (N_p x M) and y = L^-1 nu, where S = L L^T:
     * x_p += W_p y (= K_p nu), P_pa -= W_p W_a^T (= K_p S K_a^T), and each own block
     * P_pp -= W_p,blk W_p,blk^T (= K_p S K_p^T restricted to the block).
     */
    void applyUpdate(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_a, const Eigen::VectorXd& y);
    /** applyUpdate's covariance part alone (an update whose mean comes from another
     *  linearisation: EkfSlam::Options::iterated_covariance). */
    void applyCovarianceUpdate(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_a);
    /** x_p += W_p y: applyUpdate's mean part alone. */
    void applyMeanUpdate(const Eigen::MatrixXd& W_p, const Eigen::VectorXd& y);
    /** All passive means stacked (N_p). */
    const Eigen::VectorXd& meanAll() const { return mean_; }
    /**
     * EkfSlam's LinearisationPoint::Invariant, after an update: each block's position (its
     * first two entries) moved from `before` is moved by V dp instead of dp, and the
     * covariances are carried by M = I + b e^T (e the vehicle heading): b_a is the active
     * part of b, c_a = P_aa e and sigma = e^T P_aa e, read before P_aa is carried.
     */
    void invariantRetraction(const Eigen::VectorXd& before, const Eigen::Matrix2d& V, const Eigen::VectorXd& b_a,
                             const Eigen::VectorXd& c_a, double sigma);
    /** A new active block was appended: its cross-covariance with the passive rows. */
    void appendActiveColumns(const Eigen::MatrixXd& new_cols);
    /** The active entries [a, a + dim) became rho x_a + (1 - rho) x_l (+ independent
     *  noise): their cross-covariance columns follow (EkfSlam::relaxBlockTowards). */
    void blendActiveColumns(size_t a, size_t l, size_t dim, double rho);
    /** Active entries [offset, offset + dim) were removed (marginalised out). */
    void removeActiveColumns(size_t offset, size_t dim);
    /** The active state was reset: drops every passive block. */
    /** Saved run state (hymm-slam --save-state): every member a later step reads, bit
     *  for bit; loadState() replaces them (options come from the config). Throws
     *  std::runtime_error on a corrupt or truncated state. Source: EkfSlamState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

    void clear();

private:
    struct Block
    {
        long id;
        int dim;
        size_t row;  //!< first row in mean_ / cross_
    };
    std::vector<Block> blocks_;
    std::unordered_map<long, size_t> index_;
    Eigen::VectorXd mean_;
    Eigen::MatrixXd cross_;               //!< N_p x n_active
    std::vector<Eigen::MatrixXd> own_;    //!< own covariance per block
    const Block& block(long id) const;
};

}  // namespace hymm::ekf
