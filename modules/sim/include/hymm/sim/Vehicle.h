/**
 * @file Vehicle.h
 * @brief The simulated vehicle: the UTE (Ackermann) model of thesis Appendix A moved by
 *        the true controls, and the noisy readings of those controls that odometry reports.
 *
 * The state is the pose of the tracked point, (a, b) from the rear-axle centre (Eq. A.2):
 * with the UTE defaults that point is the laser, as in the thesis, so a laser mounted
 * there has a zero pose on the vehicle. Set a = b = 0 to track the rear axle instead and
 * give the sensors their offsets in their own sections. Controls are u = (v_e, alpha):
 * the speed of the encoder on the back left wheel and the steering angle; each reading
 * of a control carries independent Gaussian noise.
 */
#pragma once

#include <hymm/core/UteVehicleModel.h>
#include <hymm/core/OptionTable.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/random/RandomGenerators.h>

#include <Eigen/Core>
#include <cmath>

namespace hymm::sim
{
class Vehicle
{
public:
    /** Section [Vehicle]. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        double wheelbase_m = 2.83;                //!< L [m]
        double encoder_offset_m = 0.76;           //!< H: lateral offset of the speed encoder [m]
        double offset_a_m = 3.78;                 //!< a: tracked point forward of the rear axle [m]
        double offset_b_m = 0.50;                 //!< b: tracked point left of the rear axle [m]
        double speed_mps = 3.0;                   //!< encoder speed driven (0: parked) [m/s]
        double max_steering = 30.0 * M_PI / 180;  //!< steering limit [rad] (ini: _deg)
        double std_speed_mps = 0.3;               //!< noise of one speed reading [m/s]
        double std_steering =
            3.0 * M_PI / 180;  //!< noise of one steering reading [rad] (ini: _deg)
        /** A constant error of the steering sensor [rad] (ini: _deg): the odometry turns
         *  about offset / L per metre more than the vehicle, a systematic error that its
         *  covariance does not describe. */
        double steering_offset = 0;
        /** The odometry reports this much less turn per metre travelled than the vehicle
         *  made [rad/m] (ini: odometry_turn_loss_deg_per_m): wheels of unequal radii, a
         *  systematic error its covariance does not describe (nor does anything else:
         *  unlike steering_offset, the speed and the position are as measured). */
        double odometry_turn_loss = 0;
        /** Odometry reports the conditional mean of the increment given the noisy
         *  readings (hymm::core::uteIncrementNoiseBias subtracted), which its covariance
         *  describes; false: the raw increments of the readings, biased in heading. */
        bool odometry_bias_correction = true;

        hymm::core::UteParams ute() const;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();

        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                              const std::string& section) const override;
    };

    Vehicle(const Options& options, const Eigen::Vector3d& start_pose);

    /** One Euler step of Eq. A.4 (hymm::core::uteStep) with the true control `u`. */
    void step(const Eigen::Vector2d& u, double dt);

    /** What the speed encoder and steering sensor read for the true control `u`. */
    Eigen::Vector2d readControls(const Eigen::Vector2d& u,
                                 mrpt::random::CRandomGenerator& rng) const;

    const Eigen::Vector3d& pose() const { return pose_; }
    const Options& options() const { return options_; }

private:
    const Options options_;
    const hymm::core::UteParams ute_;
    Eigen::Vector3d pose_;
};

}  // namespace hymm::sim
