#include "hymm/core/turn_bias.h"

#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>
#include <cmath>

namespace hymm::core
{
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

}  // namespace hymm::core
