#include "hymm/core/RangeBearingModel.h"

#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <stdexcept>

namespace hymm::core
{
Vec3 sensorGlobalPose(const Vec3& v, const Vec3& s, Eigen::Matrix3d* J)
{
    const double c = std::cos(v[2]), sn = std::sin(v[2]);
    Vec3 g(v[0] + c * s[0] - sn * s[1], v[1] + sn * s[0] + c * s[1],
           mrpt::math::wrapToPi(v[2] + s[2]));
    if (J)
    {
        J->setIdentity();
        (*J)(0, 2) = -sn * s[0] - c * s[1];
        (*J)(1, 2) = c * s[0] - sn * s[1];
    }
    return g;
}

Vec2 observeRangeBearing(const Vec3& vehicle, const Vec3& sensor, const Vec2& lm, Mat23* H_v,
                         Mat2* H_l)
{
    Eigen::Matrix3d Js;
    const Vec3 sg = sensorGlobalPose(vehicle, sensor, H_v ? &Js : nullptr);
    const double dx = lm[0] - sg[0], dy = lm[1] - sg[1];
    const double r2 = dx * dx + dy * dy, r = std::sqrt(r2);
    if (r < 1e-9) throw std::domain_error("range-bearing model: landmark at the sensor origin");
    const Vec2 z(r, mrpt::math::wrapToPi(std::atan2(dy, dx) - sg[2]));

    // dz/d(sensor global pose) and dz/d(landmark), from Eq. 2.8.
    Mat2 Hl;
    Hl << dx / r, dy / r, -dy / r2, dx / r2;
    if (H_l) *H_l = Hl;
    if (H_v)
    {
        Mat23 Hs;
        Hs.block<2, 2>(0, 0) = -Hl;
        Hs(0, 2) = 0.0;
        Hs(1, 2) = -1.0;
        *H_v = Hs * Js;
    }
    return z;
}

Vec2 inverseRangeBearing(const Vec3& vehicle, const Vec3& sensor, const Vec2& z, Mat23* G_v,
                         Mat2* G_z)
{
    Eigen::Matrix3d Js;
    const Vec3 sg = sensorGlobalPose(vehicle, sensor, G_v ? &Js : nullptr);
    const double ang = sg[2] + z[1];
    const double c = std::cos(ang), s = std::sin(ang);
    const Vec2 lm(sg[0] + z[0] * c, sg[1] + z[0] * s);
    if (G_z) *G_z << c, -z[0] * s, s, z[0] * c;
    if (G_v)
    {
        Mat23 Gs;
        Gs << 1, 0, -z[0] * s, 0, 1, z[0] * c;
        *G_v = Gs * Js;
    }
    return lm;
}

}  // namespace hymm::core
