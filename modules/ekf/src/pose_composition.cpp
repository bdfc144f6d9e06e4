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

Eigen::Vector3d turnBiasedIncrement(const Eigen::Vector3d& d, double b, Eigen::Vector3d* J_b, Eigen::Matrix3d* J_d)
{
    const Eigen::Vector2d t = d.head<2>();
    const double len = t.norm(), a = 0.5 * b * len;
    const double c = std::cos(a), s = std::sin(a);
    Eigen::Matrix2d R;
    R << c, -s, s, c;
    const Eigen::Vector2d Rt = R * t;
    const Eigen::Vector2d perp(-Rt.y(), Rt.x());  // d(R(a) t)/da
    Eigen::Vector3d out;
    out << Rt, mrpt::math::wrapToPi(d.z() + b * len);
    if (J_b) *J_b << 0.5 * len * perp, len;
    if (J_d)
    {
        J_d->setIdentity();
        J_d->topLeftCorner<2, 2>() = R;
        if (len > 1e-12)
        {
            // The turn grows with the step's length: d len / d t = t^T / len.
            const Eigen::RowVector2d dlen = t.transpose() / len;
            J_d->topLeftCorner<2, 2>() += 0.5 * b * perp * dlen;
            J_d->block<1, 2>(2, 0) = b * dlen;
        }
    }
    return out;
}

}  // namespace hymm::ekf
