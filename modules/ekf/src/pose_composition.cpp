#include "hymm/ekf/pose_composition.h"

#include <mrpt/math/wrap2pi.h>

#include <cmath>

namespace hymm::ekf
{
Eigen::Vector3d composePose(
    const Eigen::Vector3d& x, const Eigen::Vector3d& d, Eigen::Matrix3d* J_x, Eigen::Matrix3d* J_d)
{
    const double c = std::cos(x[2]), s = std::sin(x[2]);
    const Eigen::Vector3d out(
        x[0] + c * d[0] - s * d[1], x[1] + s * d[0] + c * d[1], mrpt::math::wrapToPi(x[2] + d[2]));
    if (J_x)
    {
        // Only the heading couples into the position: d(R(phi) d_xy)/dphi.
        J_x->setIdentity();
        (*J_x)(0, 2) = -s * d[0] - c * d[1];
        (*J_x)(1, 2) = c * d[0] - s * d[1];
    }
    if (J_d)
    {
        J_d->setZero();
        (*J_d)(0, 0) = c;
        (*J_d)(0, 1) = -s;
        (*J_d)(1, 0) = s;
        (*J_d)(1, 1) = c;
        (*J_d)(2, 2) = 1.0;
    }
    return out;
}

}  // namespace hymm::ekf
