#include "hymm/sim/OdometryAccumulator.h"

#include <hymm/core/turn_bias.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>

namespace hymm::sim
{
OdometryAccumulator::OdometryAccumulator(const hymm::core::UteParams& ute, double std_speed,
                                         double std_steering, bool correct_bias, double turn_loss)
    : ute_(ute), correct_bias_(correct_bias), turn_loss_(turn_loss)
{
    Q_ = Eigen::Vector2d(std_speed * std_speed, std_steering * std_steering).asDiagonal();
    reset();
}

void OdometryAccumulator::reset()
{
    mean_.setZero();
    cov_.setZero();
    steps_ = 0;
}

Eigen::Vector3d OdometryAccumulator::increment(const Eigen::Vector2d& u, double dt,
                                               Eigen::Matrix<double, 3, 2>* J_u) const
{
    const Eigen::Vector3d d = hymm::core::uteIncrement(u, dt, ute_, J_u);
    if (!correct_bias_) return d;
    return d - hymm::core::uteIncrementNoiseBias(u, dt, ute_, Q_);
}

Eigen::Vector3d OdometryAccumulator::addStep(const Eigen::Vector2d& u, double dt)
{
    Eigen::Matrix<double, 3, 2> Ju;
    Eigen::Vector3d d = increment(u, dt, &Ju);
    if (turn_loss_ != 0)
    {
        // Wheels that lose turn_loss per metre report the increment turned by -turn_loss.
        Eigen::Matrix3d Jd;
        d = hymm::core::turnBiasedIncrement(d, -turn_loss_, nullptr, &Jd);
        Ju = (Jd * Ju).eval();
    }
    const double c = std::cos(mean_[2]), s = std::sin(mean_[2]);

    Eigen::Matrix3d JD = Eigen::Matrix3d::Identity();  // d(D (+) d)/dD
    JD(0, 2) = -s * d[0] - c * d[1];
    JD(1, 2) = c * d[0] - s * d[1];
    Eigen::Matrix3d Jd = Eigen::Matrix3d::Identity();  // d(D (+) d)/dd
    Jd.block<2, 2>(0, 0) << c, -s, s, c;

    cov_ = JD * cov_ * JD.transpose() + Jd * (Ju * Q_ * Ju.transpose()) * Jd.transpose();
    mean_ = Eigen::Vector3d(mean_[0] + c * d[0] - s * d[1], mean_[1] + s * d[0] + c * d[1],
                            mrpt::math::wrapToPi(mean_[2] + d[2]));
    ++steps_;
    return d;
}

Eigen::Matrix3d OdometryAccumulator::covariance() const
{
    const Eigen::Vector3d floor(kFloorStdXy * kFloorStdXy, kFloorStdXy * kFloorStdXy,
                                kFloorStdPhi * kFloorStdPhi);
    return cov_ + Eigen::Matrix3d(floor.asDiagonal());
}

}  // namespace hymm::sim
