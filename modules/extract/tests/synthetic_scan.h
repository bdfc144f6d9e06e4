/**
 * @file synthetic_scan.h
 * @brief A tiny analytic ray-caster for the extractor tests: circles (trunks, beacons) and
 *        line segments (walls, reflective tape) seen by a planar laser at a known pose.
 */
#pragma once

#include <Eigen/Core>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace hymm::extract::testing
{
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

struct Disc
{
    Eigen::Vector2d centre;  //!< world frame [m]
    double radius;           //!< [m]
    int intensity = 50;
};

struct Segment
{
    Eigen::Vector2d a, b;  //!< world frame [m]
    int intensity = 50;
};

struct World
{
    std::vector<Disc> discs;
    std::vector<Segment> walls;
};

/** Planar laser: `beams` rays over `aperture`, counter-clockwise, as MRPT's getScanAngle. */
struct Laser
{
    size_t beams = 361;
    double aperture = kPi;
    double max_range = 30.0;
    double range_noise = 0.0;  //!< std of additive Gaussian range noise [m]
    unsigned seed = 1;
    bool intensity = false;
};

inline double rayDisc(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Disc& c)
{
    const Eigen::Vector2d oc = c.centre - o;
    const double proj = d.dot(oc);
    const double disc = proj * proj - (oc.squaredNorm() - c.radius * c.radius);
    if (disc < 0) return std::numeric_limits<double>::infinity();
    const double t = proj - std::sqrt(disc);
    return t > 0 ? t : std::numeric_limits<double>::infinity();
}

inline double raySegment(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Segment& s)
{
    const Eigen::Vector2d e = s.b - s.a;
    const double den = d.x() * (-e.y()) - d.y() * (-e.x());
    if (std::abs(den) < 1e-15) return std::numeric_limits<double>::infinity();
    const Eigen::Vector2d w = s.a - o;
    // Solve o + t d = a + u e  ->  t d - u e = w (Cramer's rule).
    const double t = (w.x() * (-e.y()) - w.y() * (-e.x())) / den;
    const double u = (d.x() * w.y() - d.y() * w.x()) / den;
    if (t <= 0 || u < 0 || u > 1) return std::numeric_limits<double>::infinity();
    return t;
}

/**
 * Casts the scan from the sensor at global pose (x, y, phi). Beams that hit nothing
 * within max_range are flagged invalid with range = max_range, as real drivers do.
 * `mounting` is stored as the scan's sensorPose (it does not affect the ray casting).
 */
inline mrpt::obs::CObservation2DRangeScan castScan(
    const World& world, const Eigen::Vector3d& sensor_global, const Laser& laser,
    const mrpt::poses::CPose3D& mounting = mrpt::poses::CPose3D())
{
    mrpt::obs::CObservation2DRangeScan scan;
    scan.aperture = static_cast<float>(laser.aperture);
    scan.rightToLeft = true;
    scan.maxRange = static_cast<float>(laser.max_range);
    scan.sensorPose = mounting;
    scan.sensorLabel = "LASER";
    scan.resizeScan(laser.beams);
    scan.setScanHasIntensity(laser.intensity);
    std::mt19937 rng(laser.seed);
    std::normal_distribution<double> noise(0.0, 1.0);
    const Eigen::Vector2d o = sensor_global.head<2>();
    for (size_t i = 0; i < laser.beams; ++i)
    {
        const double a = sensor_global[2] + scan.getScanAngle(i);
        const Eigen::Vector2d d(std::cos(a), std::sin(a));
        double best = std::numeric_limits<double>::infinity();
        int inten = 0;
        for (const auto& c : world.discs)
        {
            const double t = rayDisc(o, d, c);
            if (t < best) best = t, inten = c.intensity;
        }
        for (const auto& s : world.walls)
        {
            const double t = raySegment(o, d, s);
            if (t < best) best = t, inten = s.intensity;
        }
        const bool hit = best < laser.max_range;
        double r = hit ? best : laser.max_range;
        if (hit && laser.range_noise > 0) r += laser.range_noise * noise(rng);
        scan.setScanRange(i, static_cast<float>(r));
        scan.setScanRangeValidity(i, hit);
        if (laser.intensity) scan.setScanIntensity(i, hit ? inten : 0);
    }
    return scan;
}

/** World position of a point given in the sensor frame by (range, bearing). */
inline Eigen::Vector2d worldFromSensor(const Eigen::Vector3d& sensor, double range, double bearing)
{
    const double a = sensor[2] + bearing;
    return sensor.head<2>() + range * Eigen::Vector2d(std::cos(a), std::sin(a));
}

/** Sensor-frame position of a world point. */
inline Eigen::Vector2d sensorFromWorld(const Eigen::Vector3d& sensor, const Eigen::Vector2d& p)
{
    const Eigen::Vector2d d = p - sensor.head<2>();
    const double c = std::cos(sensor[2]), s = std::sin(sensor[2]);
    return Eigen::Vector2d(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
}

}  // namespace hymm::extract::testing
