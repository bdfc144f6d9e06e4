/**
 * @file PointSet.cpp
 * @brief Scan points as Gaussians and SE(2) helpers.
 */
#include "hymm/scanslam/PointSet.h"

#include <mrpt/math/wrap2pi.h>

#include <cmath>

namespace hymm::scanslam
{
Mat2 polarJacobian(double r, double b)
{
    const double c = std::cos(b), s = std::sin(b);
    Mat2 j;
    j << c, -r * s, s, r * c;
    return j;
}

Mat2 polarCovariance(double r, double b, const ScanNoise& noise)
{
    const Mat2 j = polarJacobian(r, b);
    const Eigen::Vector2d var(noise.std_range_m * noise.std_range_m,
                              noise.std_bearing * noise.std_bearing);
    Mat2 c = j * var.asDiagonal() * j.transpose();
    return 0.5 * (c + c.transpose());
}

PointSet fromScan(const mrpt::obs::CObservation2DRangeScan& scan, const ScanNoise& noise,
                  ScanReadStats* stats)
{
    PointSet out;
    ScanReadStats st;
    const size_t n = scan.getScanSize();
    st.beams = n;
    out.points.reserve(n);
    out.covs.reserve(n);
    out.range.reserve(n);
    out.bearing.reserve(n);
    // Beam angles as MRPT lays them out (aperture centred ahead, rightToLeft flag).
    const double a0 = -0.5 * scan.aperture;
    const double da = n > 1 ? scan.aperture / static_cast<double>(n - 1) : 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        const double r = scan.getScanRange(i);
        if (!scan.getScanRangeValidity(i))
        {
            ++st.invalid;
            continue;
        }
        if (!std::isfinite(r))
        {
            ++st.non_finite;
            continue;
        }
        if (r <= 0 || r >= scan.maxRange)
        {
            ++st.out_of_range;
            continue;
        }
        const double k = scan.rightToLeft ? static_cast<double>(i) : static_cast<double>(n - 1 - i);
        const double b = a0 + k * da;
        out.points.emplace_back(r * std::cos(b), r * std::sin(b));
        out.covs.push_back(polarCovariance(r, b, noise));
        out.range.push_back(r);
        out.bearing.push_back(b);
        ++st.used;
    }
    if (stats) *stats = st;
    return out;
}

Vec3 compose(const Vec3& a, const Vec3& b)
{
    const Vec2 p = transformPoint(a, b.head<2>());
    return {p.x(), p.y(), mrpt::math::wrapToPi(a.z() + b.z())};
}

Vec3 inverse(const Vec3& a)
{
    const double c = std::cos(a.z()), s = std::sin(a.z());
    return {-c * a.x() - s * a.y(), s * a.x() - c * a.y(), mrpt::math::wrapToPi(-a.z())};
}

Vec3 poseDifference(const Vec3& a, const Vec3& b)
{
    return {a.x() - b.x(), a.y() - b.y(), mrpt::math::wrapToPi(a.z() - b.z())};
}

std::vector<Vec2> transformedPoints(const std::vector<Vec2>& points, const Vec3& z)
{
    std::vector<Vec2> out;
    out.reserve(points.size());
    for (const Vec2& p : points) out.push_back(transformPoint(z, p));
    return out;
}

PointSet transformed(const PointSet& set, const Vec3& z)
{
    PointSet out = set;
    const Mat2 r = rotation(z.z());
    for (size_t i = 0; i < set.size(); ++i)
    {
        out.points[i] = transformPoint(z, set.points[i]);
        out.covs[i] = r * set.covs[i] * r.transpose();
    }
    return out;
}

}  // namespace hymm::scanslam
