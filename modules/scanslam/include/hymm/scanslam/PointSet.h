/**
 * @file PointSet.h
 * @brief Scan points as Gaussians (thesis 5.3.1: a scan is a sum of Gaussians, each
 *        point's range/bearing noise projected into the plane), read from an MRPT scan,
 *        and the SE(2) helpers the matchers share.
 *
 * A pose z = (x, y, phi) maps a point p of its frame to R(phi) p + (x, y) in the parent
 * frame. Scan points live in the sensor frame; template points in the landmark frame.
 */
#pragma once

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace hymm::scanslam
{
using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

/** Points with 2x2 covariances; `range`/`bearing` are kept for points read from a
 *  scan (segmentation needs them) and empty otherwise. */
struct PointSet
{
    std::vector<Vec2> points;
    std::vector<Mat2> covs;
    std::vector<double> range;    //!< [m], same size as points or empty
    std::vector<double> bearing;  //!< [rad], same size as points or empty

    size_t size() const { return points.size(); }
    bool empty() const { return points.empty(); }
    void add(const Vec2& p, const Mat2& c)
    {
        points.push_back(p);
        covs.push_back(c);
    }
};

/** Sensor noise of a range-bearing scanner. */
struct ScanNoise
{
    double std_range_m = 0.1;
    double std_bearing = M_PI / 180;  //!< [rad]
};

/** What fromScan() skipped. */
struct ScanReadStats
{
    size_t beams = 0;
    size_t used = 0;
    size_t invalid = 0;    //!< flagged invalid by the scan
    size_t non_finite = 0; //!< NaN / inf range
    size_t out_of_range = 0;  //!< <= 0 or >= maxRange
};

/** d(x, y)/d(r, b) of (r cos b, r sin b). */
Mat2 polarJacobian(double r, double b);

/** Point covariance J diag(sr^2, sb^2) J^T (the noise projected into the plane, 5.2.1). */
Mat2 polarCovariance(double r, double b, const ScanNoise& noise);

/** Valid returns of `scan` as points in the sensor frame with projected covariances;
 *  invalid, non-finite and out-of-range readings are skipped and counted in `stats`. */
PointSet fromScan(const mrpt::obs::CObservation2DRangeScan& scan, const ScanNoise& noise,
                  ScanReadStats* stats = nullptr);

/** R(z.phi) p + z.xy */
inline Vec2 transformPoint(const Vec3& z, const Vec2& p)
{
    const double c = std::cos(z.z()), s = std::sin(z.z());
    return {c * p.x() - s * p.y() + z.x(), s * p.x() + c * p.y() + z.y()};
}

inline Mat2 rotation(double phi)
{
    Mat2 r;
    r << std::cos(phi), -std::sin(phi), std::sin(phi), std::cos(phi);
    return r;
}

/** a (+) b: pose b given in frame a, expressed in a's parent. */
Vec3 compose(const Vec3& a, const Vec3& b);
/** (-) a */
Vec3 inverse(const Vec3& a);
/** a - b with the angle wrapped to (-pi, pi]. */
Vec3 poseDifference(const Vec3& a, const Vec3& b);

/** `set` transformed by z: points and covariances (R C R^T). */
PointSet transformed(const PointSet& set, const Vec3& z);
/** The points alone transformed by z (a template placed at a pose). */
std::vector<Vec2> transformedPoints(const std::vector<Vec2>& points, const Vec3& z);

}  // namespace hymm::scanslam
