/**
 * @file EkfSlam.h
 * @brief EKF feature SLAM (thesis chapter 2): vehicle pose plus landmark blocks with
 *        full correlations, UTE / odometry prediction, batched range-bearing updates,
 *        exact augmentation (Eq. 2.53), data association (known ids, NN or JCBB), pruning
 *        of tentative landmarks and passive states with Unidirectional Information Flow.
 *        Jacobians at the current estimate (standard EKF) or at first estimates (FEJ-EKF,
 *        Huang, Mourikis & Roumeliotis, ICRA 2008; see LinearisationPoint).
 *
 * Costs with n active states and m associated observations per step:
 *  - prediction O(n): only P_vv and the vehicle-map cross block P_vm change (Eq. 2.36);
 *  - update O(n^2 m): P H^T is gathered from the vehicle and one landmark block per
 *    observation (O(n m), never a dense H times P), then P -= W W^T is one symmetric
 *    rank-2m update with W = P H^T L^-T, S = L L^T (Eq. 2.44-2.47 rearranged);
 *  - augmentation O(n k) for k new landmarks: the covariance lives in storage with spare
 *    capacity (grown 1.5x when full, O(log n) reallocations over a growing map) and new
 *    rows and columns are written in place;
 *  - removal of a block at offset o O(n (n - o)) in place (pruned tentative landmarks are
 *    the most recent, at the end of the state).
 */
#pragma once

#include <hymm/core/TimeLogger.h>
#include <hymm/core/OptionTable.h>
#include <hymm/core/UteVehicleModel.h>
#include <hymm/ekf/DataAssociation.h>
#include <hymm/ekf/LinearisationOptions.h>
#include <hymm/ekf/PassiveStates.h>
#include <hymm/ekf/StateLayout.h>
#include <hymm/ekf/UpdateReports.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <Eigen/Core>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace mrpt::serialization
{
class CArchive;
}

namespace hymm::ekf
{
class EkfSlam
{
public:
    /** Ini section [EkfSlam]; unknown keys are errors, absent keys keep the defaults. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        /** Association of observations without id: NN (Eq. 2.60) or JCBB. Ini:
         *  association_method = nn | jcbb. */
        AssociationMethod association_method = AssociationMethod::NearestNeighbour;
        /** Chi-square probability of the individual and joint association gates. */
        double association_gate_prob = 0.99;
        /** Chi-square probability of the creation gate (> association_gate_prob): an
         *  observation inside it for some landmark but associated with none is ambiguous. */
        double creation_gate_prob = 0.9999;
        /** Outlier gate for observations with a known id (0: off, every one is fused):
         *  one whose innovation NIS exceeds chi2inv(p, 2) is rejected and counted in
         *  UpdateReport::rejected_gate. Real sensors have heavy-tailed errors (wrong
         *  ranges, mislabelled barcodes) that an identity does not protect against. */
        double known_id_gate_prob = 0.0;
        size_t jcbb_max_nodes = 100000;  //!< JCBB node budget per step (0: unlimited)
        bool prune_tentative = true;     //!< remove landmarks that are never confirmed
        /** A landmark is confirmed once used by this many observations (creation counts). */
        int confirm_min_observations = 2;
        /** Unconfirmed landmarks older than this many update steps are removed. */
        int confirm_window_steps = 5;
        /** Additive stabilising noise per prediction (thesis Eq. 2.6's v), std dev. */
        double stabilising_std_xy = 0.0;   //!< [m]
        double stabilising_std_phi = 0.0;  //!< [rad] (ini: stabilising_std_phi_deg)
        bool enable_profiler = false;      //!< CTimeLogger sections "ekf.*"
        /** Linearisation points of the Jacobians. Ini: jacobians = current |
         *  first_estimates | invariant. */
        LinearisationPoint jacobians = LinearisationPoint::Current;
        /** Second-order EKF terms of the pose-landmark update (poseObservationSecondOrder):
         *  S only (Covariance) or S and the predicted observation (Full). Ini: off |
         *  covariance | full (README, "Second-order terms of the pose update"). */
        SecondOrderTerms pose_update_second_order = SecondOrderTerms::Off;
        /** Covariance of an iterated pose-landmark update (max_iterations > 1): the
         *  Jacobians of the last iterate (the iterated EKF) or those of the one-step update
         *  (FEJ-EKF's with jacobians = first_estimates, at the prior with invariant), the
         *  mean still the iterated one.
         *  Ini: last_iterate | first_estimates (README, "Iterated updates with
         *  first-estimates covariance"). */
        IteratedCovariance iterated_covariance = IteratedCovariance::LastIterate;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        /** Throws std::invalid_argument naming the section, key and value. */
        void validate(const std::string& section = "EkfSlam") const;
    };

    /** Throws std::invalid_argument on invalid options. Starts at the origin with zero
     *  covariance and no landmarks. */
    explicit EkfSlam(const Options& options);
    EkfSlam(const EkfSlam&) = default;  // value semantics: a copy is an independent filter
    EkfSlam& operator=(const EkfSlam&) = delete;

    const Options& options() const { return options_; }

    /** Drops every landmark and passive block; sets the vehicle pose and covariance. */
    void reset(const Eigen::Vector3d& pose, const Eigen::Matrix3d& cov);

    // ---- Prediction (Eq. 2.33-2.36) ----

    /** UTE model step (hymm::core::uteStep) with control u = (v_encoder, steering) of
     *  covariance Q over dt seconds: P_vv = F P_vv F^T + B Q B^T (+ stabilising noise),
     *  P_vm = F P_vm. */
    void predictUte(const Eigen::Vector2d& u, const Eigen::Matrix2d& Q, double dt,
                    const hymm::core::UteParams& p);
    /** Odometry increment d ~ N(mean, cov) in the vehicle frame: x <- x (+) d. */
    void predictOdometry(const mrpt::poses::CPosePDFGaussian& increment);
    /** As above from an MRPT action (its poseChange PDF, converted to a Gaussian). */
    void predictOdometry(const mrpt::obs::CActionRobotMovement2D& action);
    /** predictOdometry with the wheels' turn bias b [rad/m] as the state of the 1-DOF
     *  block `bias` (addAuxiliaryBlock): x <- x (+) core::turnBiasedIncrement(d, b), so the
     *  vehicle's rows become F x_v + G b (G = d/db, at the estimate) and the correlation
     *  the bias builds up between steps is kept; b then walks: P_bb += walk_var s, s the
     *  increment's length [m]. Throws on an unknown or non-1-DOF `bias`, a bad increment
     *  or walk_var < 0, and with jacobians = invariant (not derived for it). */
    void predictOdometryWithTurnBias(const mrpt::poses::CPosePDFGaussian& increment, long bias, double walk_var);

    // ---- Update ----

    /**
     * Associates, fuses and augments one batch of observations taken by a sensor at
     * `sensorPoseOnVehicle` (x, y, yaw used). All associated observations are fused in one
     * batched update; new landmarks are then added with the exact augmentation of Eq. 2.53
     * at the updated vehicle pose. Invalid observations are skipped and counted, never
     * thrown. Ends the step: tentative landmarks are confirmed or pruned.
     */
    UpdateReport updateRangeBearing(const std::vector<RangeBearingObs>& obs,
                                    const mrpt::poses::CPose3D& sensorPoseOnVehicle);

    // ---- Active state access ----

    Eigen::Vector3d vehiclePose() const { return x_.head<3>(); }
    Eigen::Matrix3d vehicleCov() const { return activeP().topLeftCorner<3, 3>(); }
    size_t numLandmarks() const;            //!< every block but the auxiliary ones
    std::vector<long> landmarkIds() const;  //!< the same, in state order
    bool hasLandmark(long id) const { return layout_.has(id); }
    const LandmarkBlock& landmarkBlock(long id) const { return layout_.get(id); }
    /** Mean / covariance of a 2D point landmark; throws if unknown or not 2-DOF. */
    Eigen::Vector2d landmarkMean(long id) const;
    Eigen::Matrix2d landmarkCov(long id) const;
    /** Any landmark block (2-DOF points, 3-DOF poses, ...). */
    Eigen::VectorXd landmarkBlockMean(long id) const;
    Eigen::MatrixXd landmarkBlockCov(long id) const;
    const Eigen::VectorXd& mean() const { return x_; }  //!< active states
    /** Covariance of the active states: a view of the filter's storage (n x n, outer
     *  stride = the storage's capacity), valid until the state size changes (an update
     *  that adds or prunes landmarks, addLandmark, removeLandmark, reset, setActiveState).
     *  Assign it to an Eigen::MatrixXd to keep a copy. */
    Eigen::Ref<const Eigen::MatrixXd> cov() const { return activeP(); }
    const StateLayout& layout() const { return layout_; }
    long currentStep() const { return step_; }

    // ---- Linearisation points (see LinearisationPoint) ----

    /** The block's first estimate: its mean when it was added (augmentation, addLandmark or
     *  setActiveState). Throws if unknown. */
    const Eigen::VectorXd& landmarkFirstEstimate(long id) const;
    /** The vehicle pose of the latest prediction before any update, x_{k|k-1} (the pose
     *  of reset() or setActiveState() before the first prediction). */
    const Eigen::Vector3d& predictedPose() const { return predicted_pose_; }
    /** The vehicle Jacobian F of the latest prediction (identity before the first one). */
    const Eigen::Matrix3d& lastMotionJacobian() const { return last_F_; }
    /** The Jacobians of the range-bearing observation of point landmark `id` that the next
     *  update would use (d h / d vehicle, d h / d landmark), for a sensor at (x, y, yaw) on
     *  the vehicle. Throws if unknown or not a 2D point. */
    void observationJacobians(long id, const Eigen::Vector3d& sensor,
                              Eigen::Matrix<double, 2, 3>& H_v, Eigen::Matrix2d& H_l) const;
    /** The same for pose landmark `id` (updatePoseLandmark with one iteration). Throws if
     *  unknown or not a 3-DOF block. */
    void poseObservationJacobians(long id, const Eigen::Vector3d& sensor, Eigen::Matrix3d& H_v,
                                  Eigen::Matrix3d& H_l) const;

    /**
     * Adds an active landmark block by the augmentation of Eq. 2.53 for any block size:
     * mean `mean`, P_new = G_v P_vv G_v^T + noise_cov, P_new,* = G_v P_v*. `noise_cov`
     * is the measurement term (G_z R G_z^T). id < 0 picks a fresh id. The block starts
     * confirmed (it was not created from a single gated observation). Returns the id.
     */
    long addLandmark(const Eigen::VectorXd& mean, const Eigen::MatrixXd& G_v,
                     const Eigen::MatrixXd& noise_cov, long id = -1);
    // ---- 3-DOF pose landmarks (Scan-SLAM, thesis ch. 5; EkfSlamPoseLandmarks.cpp) ----

    /** Adds a pose landmark from its observation z (landmark frame in the sensor frame,
     *  covariance R) by exact augmentation (pose_landmark_model.h). Returns the id. */
    long addPoseLandmark(const Eigen::Vector3d& z, const Eigen::Matrix3d& R,
                         const Eigen::Vector3d& sensor, long id = -1);
    /** Updates with an observation of pose landmark `id`, gated at `gate_prob` of
     *  chi-square(3) (0 or 1: no gate). Throws if `id` is unknown or not 3-DOF; bad
     *  input and numeric failures leave the state untouched and are reported.
     *  `max_iterations` > 1: iterated EKF, the observation relinearised at the updated
     *  vehicle and landmark poses until they move less than 1e-9 (the gate uses the
     *  prior's linearisation); 1: the EKF update, with LinearisationPoint::FirstEstimates
     *  its H at x_{k|k-1} and the landmark's first estimate. */
    PoseUpdateReport updatePoseLandmark(long id, const Eigen::Vector3d& z,
                                        const Eigen::Matrix3d& R, const Eigen::Vector3d& sensor,
                                        double gate_prob, int max_iterations = 1);

    /** Updates with an observation z of pose landmark `id` as seen from pose landmark
     *  `observer` (z = x_observer^-1 (+) x_id, the model of updatePoseLandmark with the
     *  observer in the vehicle's place and no mounting), e.g. the alignment of one template
     *  with another that is a second landmark on the same object. Gate and bad input as
     *  updatePoseLandmark, and so are the iterations (`max_iterations` > 1: iterated EKF);
     *  with one, first-estimates Jacobians at both blocks' first estimates. */
    PoseUpdateReport updateRelativePose(long observer, long id, const Eigen::Vector3d& z,
                                        const Eigen::Matrix3d& R, double gate_prob, int max_iterations = 1);

    // ---- Auxiliary blocks (correlated observation errors as states; EkfSlamAuxiliary.cpp) ----

    /** Adds an auxiliary block (not a landmark: LandmarkBlock::auxiliary) = block `src` +
     *  independent noise: mean x_src, cov P_src,src + noise_cov, cross P_src,* (active and
     *  passive), src's first estimate; id < 0: fresh. Throws on an unknown src, a used id
     *  or noise_cov not dim x dim PSD. E.g. a scan template's apparent pose. */
    long addBlockCopy(long src, const Eigen::MatrixXd& noise_cov, long id = -1);
    /** Gauss-Markov step of block a about block l (same dim): a <- l + rho (a - l) + w,
     *  w ~ N(0, Q); P <- T P T^T + Q (T: rows a = [rho I at a, (1 - rho) I at l]), passive
     *  cross-covariances alike, angles wrapped. Exact in the invariant EKF's coordinates
     *  too (affine combinations commute with SE(2)). Throws on unknown ids, other dims,
     *  a == l, rho outside [0, 1], Q not PSD. */
    void relaxBlockTowards(long a, long l, double rho, const Eigen::MatrixXd& Q);

    /** Adds an auxiliary block independent of every other state (mean, covariance `cov`),
     *  e.g. a bias parameter with its prior. Throws on a used id or `cov` not PSD. */
    long addAuxiliaryBlock(const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov, long id = -1);
    /** Adds an auxiliary copy of the vehicle pose (stochastic cloning: mean x_v, P_vv,
     *  cross P_v*, active and passive), e.g. the pose at a reference scan that later scans
     *  are aligned to (updateVehicleFromCopy). */
    long addVehicleCopy(long id = -1);
    /** The vehicle copied again into the existing copy `copy` (addVehicleCopy), in place:
     *  O(n), where removing the block and adding a new one moves O(n^2) entries. Throws
     *  if `copy` is unknown or not 3-DOF. */
    void recopyVehicle(long copy);
    /** Updates with z = x_copy^-1 (+) x_v (the vehicle seen from the 3-DOF block `copy`,
     *  e.g. a scan alignment to the reference scan taken at the copy), gated at `gate_prob`
     *  of chi-square(3) (0 or 1: no gate); EKF step at the current estimate (with
     *  first-estimates Jacobians: x_{k|k-1} and the copy's first estimate). Bad input and
     *  numeric failures leave the state untouched and are reported. */
    PoseUpdateReport updateVehicleFromCopy(long copy, const Eigen::Vector3d& z, const Eigen::Matrix3d& R,
                                           double gate_prob);

    /** Marginalises a landmark out (deletes its rows and columns). Throws if unknown. */
    void removeLandmark(long id);

    /** Replaces the whole active state (checkpoints, tests, benchmarks). `blocks` lists
     *  (id, dim) in state order after the vehicle; landmarks start confirmed. Drops passive
     *  blocks. Throws on size mismatch, non-finite or non-symmetric covariance. */
    void setActiveState(const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                        const std::vector<std::pair<long, int>>& blocks);

    // ---- Passive states (UIF, thesis 3.7.1) ----

    /** Adds a passive block with its own covariance and its cross-covariance with the
     *  active states (dim x numActiveStates). */
    void addPassiveState(long id, const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov,
                         const Eigen::MatrixXd& cross_with_active);
    /** Passive block from a vehicle-relative measurement, as Eq. 2.53: cov = G_v P_vv
     *  G_v^T + noise_cov and cross = G_v P_v* (e.g. G_v = I, noise 0: a vehicle-pose copy). */
    void addPassiveFromVehicle(long id, const Eigen::VectorXd& mean, const Eigen::MatrixXd& G_v,
                               const Eigen::MatrixXd& noise_cov);
    /** Passive block defined on active landmarks, as Eq. 2.53 with landmarks in place of
     *  the vehicle: for mean = g(x_1, ..., x_k) with G_i = dg/dx_i, cross = sum_i G_i P_i*
     *  (P_i*: the rows of landmark i) and cov = sum_i cross_i G_i^T + noise_cov, where
     *  cross_i are the columns of landmark i (e.g. a virtual landmark, thesis Sec. 3.5.1,
     *  from the two landmarks of a region edge). Throws on an unknown id or a G_i that is
     *  not dim x landmark dim. */
    void addPassiveFromLandmarks(long id, const Eigen::VectorXd& mean,
                                 const std::vector<std::pair<long, Eigen::MatrixXd>>& G,
                                 const Eigen::MatrixXd& noise_cov);
    void removePassiveState(long id) { passive_.remove(id); }
    const PassiveStates& passive() const { return passive_; }

    /** Saved run state (hymm-slam --save-state): every member a later step reads, bit
     *  for bit; loadState() replaces them (options come from the config). Throws
     *  std::runtime_error on a corrupt or truncated state. Source: EkfSlamState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

    const mrpt::system::CTimeLogger& profiler() const { return profiler_.get(); }
    /** Mutable access, e.g. to clear it or to disable it (an enabled CTimeLogger prints
     *  its statistics when destroyed). */
    mrpt::system::CTimeLogger& profiler() { return profiler_.get(); }

private:
    struct Pairing
    {
        size_t obs;           //!< index into the observation batch
        size_t offset;        //!< landmark offset in the state
        long id;
        Eigen::Vector2d h;    //!< predicted observation
        Eigen::Matrix<double, 2, 3> Hv;
        Eigen::Matrix2d Hl;
    };
    struct NewLandmark
    {
        size_t obs;
        long id;  //!< -1: fresh id
    };

    /** Moves the vehicle to `pose` with the motion Jacobian F_current at the current estimate
     *  (FEJ replaces its position-heading block, see LinearisationPoint); with `param` >= 0
     *  the new pose also depends on the 1-DOF state at that offset through G. */
    void applyVehicleMotion(const Eigen::Vector3d& pose, const Eigen::Matrix3d& F_current, const Eigen::Matrix3d& Q,
                            Eigen::Index param = -1, const Eigen::Vector3d& G = Eigen::Vector3d::Zero());
    /** Data association of one batch; fills pairings, new landmarks and the report. */
    void associateBatch(const std::vector<RangeBearingObs>& obs, const std::vector<bool>& valid,
                        const Eigen::Vector3d& sensor, std::vector<Pairing>& pairs,
                        std::vector<NewLandmark>& created, UpdateReport& report) const;
    /** associateBatch, known ids: pairs them (gated when known_id_gate_prob > 0), marks the
     *  paired blocks in `taken`; returns the valid observations without an id. */
    std::vector<size_t> associateKnownIds(const std::vector<RangeBearingObs>& obs,
                                          const std::vector<bool>& valid, const Eigen::Vector3d& sensor,
                                          std::vector<Pairing>& pairs, std::vector<NewLandmark>& created,
                                          std::vector<bool>& taken, UpdateReport& report) const;
    /** associateBatch, the rest: free point landmarks in the creation gate of an `unknown` one. */
    std::vector<Pairing> gateCandidates(const std::vector<RangeBearingObs>& obs, const std::vector<size_t>& unknown,
                                        const std::vector<bool>& taken, const Eigen::Vector3d& sensor) const;
    /** New landmarks at the updated vehicle pose (Eq. 2.53) in one augmentation. */
    void addNewLandmarks(const std::vector<NewLandmark>& created, const std::vector<RangeBearingObs>& obs,
                         const Eigen::Vector3d& sensor, UpdateReport& report);
    /** Batched sparse update; false (state untouched) if S is not PD. */
    bool fuse(const std::vector<Pairing>& pairs, const std::vector<RangeBearingObs>& obs, std::string& reason);
    /** Eq. 2.53 for several new blocks at once: G (sum d x 3), noise blockdiag. */
    void augment(const std::vector<std::pair<long, Eigen::VectorXd>>& blocks, const Eigen::MatrixXd& G,
                 const Eigen::MatrixXd& noise, bool confirmed);
    /** Any augmentation (augment, addBlockCopy): new rows `cross` (k x n), own block Pnn. */
    void appendBlocks(const std::vector<std::pair<long, Eigen::VectorXd>>& blocks, const Eigen::MatrixXd& cross,
                      const Eigen::MatrixXd& Pnn, const Eigen::MatrixXd& passive_cols, bool confirmed);
    size_t pruneTentative();
    /** FEJ linearisation point of a one-step pose update of `id` from `observer` (-1: vehicle):
     *  (x_{k|k-1} or the observer's first estimate, the landmark's); none with `current`. */
    std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> poseFejPoint(long observer, long id) const;
    /** The active and passive means before an update (the invariant EKF's update needs them). */
    struct PriorMeans { Eigen::VectorXd active, passive; };
    /** LinearisationPoint::Invariant: the means before an update; none with other Jacobians. */
    std::optional<PriorMeans> invariantPrior() const;
    /** The covariance part of an update whose mean part (x_ += K nu, passive blocks fully
     *  updated) is done: P -= W W^T with W^T = Wt (M x n). With the invariant EKF's `prior`,
     *  the mean update is re-applied on the group first (unless !retract_mean: an iterated
     *  update keeps its mean) and P is carried to the new estimate's coordinates (active and
     *  passive). EkfSlamFuse.cpp. */
    void updateCovariance(const Eigen::MatrixXd& Wt, const std::optional<PriorMeans>& prior, bool retract_mean);
    /** updatePoseLandmark / updateRelativePose: observer -1 is the vehicle. */
    PoseUpdateReport updatePoseBlock(long observer, long id, const Eigen::Vector3d& z, const Eigen::Matrix3d& R,
                                     const Eigen::Vector3d& sensor, double gate_prob, int max_iterations);
    Pairing makePairing(size_t obs, const LandmarkBlock& b, const Eigen::Vector3d& sensor) const;

    const Options options_;
    StateLayout layout_;
    /** Active part of the covariance storage: the top-left n x n, n = x_.size(). */
    Eigen::Block<Eigen::MatrixXd> activeP() { return Pbuf_.topLeftCorner(x_.size(), x_.size()); }
    Eigen::Block<const Eigen::MatrixXd> activeP() const { return Pbuf_.topLeftCorner(x_.size(), x_.size()); }
    /** Grows the covariance storage to hold at least n states, keeping the active part. */
    void reserveStates(Eigen::Index n);

    Eigen::VectorXd x_;  //!< active states (exact size)
    /** Covariance storage, capacity x capacity with capacity >= x_.size(); only activeP()
     *  is meaningful (the rest is spare room for new landmarks). */
    Eigen::MatrixXd Pbuf_;
    PassiveStates passive_;
    /** Mean of every active block when it was added (LinearisationPoint::FirstEstimates). */
    std::unordered_map<long, Eigen::VectorXd> first_estimates_;
    Eigen::Vector3d predicted_pose_ = Eigen::Vector3d::Zero();  //!< x_{k|k-1}
    Eigen::Matrix3d last_F_ = Eigen::Matrix3d::Identity();
    long step_ = 0;
    core::LazyTimeLogger profiler_;
};

}  // namespace hymm::ekf
