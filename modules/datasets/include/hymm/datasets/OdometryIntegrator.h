/**
 * @file OdometryIntegrator.h
 * @brief Integrates time-stamped control samples (speed + steering, or speed + turn
 *        rate) into Gaussian pose increments between two arbitrary times.
 *
 * Datasets log controls at a high rate (40-50 Hz) and sensors at their own times; a
 * rawlog needs one odometry increment per sensory frame. Each control sample is held
 * from its timestamp until the next sample (zero-order hold, at most `max_hold_s`, so a
 * logging gap does not extrapolate forever), the interval [t0, t1] is cut at sample
 * boundaries, and each piece is one step of the vehicle model:
 *  - Model::Ute: hymm::core::uteIncrement (thesis Appendix A, Eq. A.4), u = (v_encoder,
 *    steering); the tracked point is (a, b) of the UteParams.
 *  - Model::Unicycle: u = (v, omega), an arc step (midpoint heading).
 * Steps are composed with their Jacobians, so the covariance of the increment is the
 * first-order propagation of the control noise Q = diag(std_u0^2, std_u1^2), taken as
 * independent per sample piece. A small floor (min_std_*) keeps it positive definite
 * when the vehicle stands still.
 */
#pragma once

#include <hymm/core/OptionTable.h>

#include <hymm/core/UteVehicleModel.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>
#include <vector>

namespace hymm::datasets
{
struct ImportSummary;

class OdometryIntegrator
{
   public:
    enum class Model
    {
        Ute,      //!< u = (encoder speed [m/s], steering [rad])
        Unicycle  //!< u = (forward speed [m/s], turn rate [rad/s])
    };

    struct Options : public mrpt::config::CLoadableOptions
    {
        double std_speed_mps = 0.1;        //!< std of one speed sample [m/s]
        double std_steering_deg = 1.0;     //!< std of one steering sample (Ute) [deg]
        double std_turn_rate_deg_s = 2.0;  //!< std of one turn-rate sample (Unicycle) [deg/s]
        double max_hold_s = 0.5;           //!< longest time a sample is held [s]
        double min_std_xy_m = 1e-3;        //!< floor added to each increment, x and y [m]
        double min_std_phi_deg = 0.01;     //!< floor added to each increment, heading [deg]

        /** Every ini key, declared once; the importers include it in their own table. */
        hymm::core::OptionTable table();
        /** Reads a section holding only the keys above (unknown keys are errors). */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        static const std::vector<std::string>& keys();
    };

    struct ControlSample
    {
        double t = 0;   //!< [s]
        double u0 = 0;  //!< speed [m/s]
        double u1 = 0;  //!< steering [rad] (Ute) or turn rate [rad/s] (Unicycle)
    };

    struct Increment
    {
        mrpt::poses::CPose2D mean;   //!< pose at t1 in the frame of the pose at t0
        Eigen::Matrix3d cov;         //!< covariance of (x, y, phi)
        double uncovered_s = 0;      //!< part of [t0, t1] with no control held [s]
        size_t steps = 0;            //!< model steps composed
    };

    /** `samples` must have strictly increasing times and valid controls (see
     *  sanitize()); throws std::invalid_argument otherwise. */
    OdometryIntegrator(Model model, const hymm::core::UteParams& ute, const Options& options,
                       std::vector<ControlSample> samples);

    /** Drops samples with non-finite values ("odometry_nan"), times not after the last
     *  accepted one ("odometry_non_monotonic") and, for Ute, steering outside the model's
     *  range ("odometry_steering_out_of_range"), counting them in `summary`. */
    static std::vector<ControlSample> sanitize(
        const std::vector<ControlSample>& raw, Model model, const hymm::core::UteParams& ute,
        ImportSummary& summary);

    /** Increment from t0 to t1 (t0 <= t1). Time before the first sample, or beyond a
     *  sample's hold, contributes no motion and is reported in `uncovered_s`. */
    Increment integrate(double t0, double t1) const;

    const std::vector<ControlSample>& samples() const { return samples_; }

   private:
    /** One model step; returns the increment and its covariance from Q. */
    Eigen::Vector3d step(const ControlSample& s, double dt, Eigen::Matrix3d& cov) const;

    const Model model_;
    const hymm::core::UteParams ute_;
    const Options options_;
    const std::vector<ControlSample> samples_;
};

}  // namespace hymm::datasets
