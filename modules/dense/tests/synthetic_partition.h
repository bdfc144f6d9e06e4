/**
 * @file synthetic_partition.h
 * @brief Test/benchmark helper: landmarks on a square lattice and an LTR partition of
 *        its triangles, built with RegionPartition::tryAddRegion.
 *
 * Landmark (i, j) sits at origin + spacing (i, j) with id 100 + i * ny + j. The
 * correlation conditions are switched off (they are the ltr module's business); the
 * geometry and overlap conditions still apply.
 */
#pragma once

#include "hymm/ltr/DenseCovarianceView.h"
#include "hymm/ltr/RegionPartition.h"

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>
#include <vector>

namespace hymm::dense::synthetic
{
/** Landmarks with independent, equal, small position uncertainty: O(1) memory per
 *  landmark (a DenseCovarianceView of 2000 landmarks would hold a 4003^2 matrix). */
class IndependentLandmarksView : public hymm::ltr::LandmarkCovarianceView
{
public:
    IndependentLandmarksView(std::map<long, Eigen::Vector2d> means, double sigma = 0.01)
        : means_(std::move(means)), var_(sigma * sigma)
    {
    }
    bool has(long id) const override { return means_.count(id) != 0; }
    Eigen::Vector2d mean(long id) const override { return means_.at(id); }
    Eigen::Matrix2d cov(long) const override { return var_ * Eigen::Matrix2d::Identity(); }
    Eigen::Matrix2d crossCov(long a, long b) const override
    {
        return a == b ? cov(a) : Eigen::Matrix2d::Zero();
    }
    Eigen::Matrix<double, 2, 3> crossVehicle(long) const override
    {
        return Eigen::Matrix<double, 2, 3>::Zero();
    }
    Eigen::Matrix3d vehicleCov() const override { return var_ * Eigen::Matrix3d::Identity(); }
    Eigen::Vector3d vehiclePose() const override { return Eigen::Vector3d::Zero(); }
    std::vector<long> ids() const override
    {
        std::vector<long> out;
        for (const auto& kv : means_) out.push_back(kv.first);
        return out;
    }
    std::map<long, Eigen::Vector2d>& means() { return means_; }

private:
    std::map<long, Eigen::Vector2d> means_;
    double var_;
};

struct Lattice
{
    int nx = 0, ny = 0;
    double spacing = 1;
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();

    long id(int i, int j) const { return 100 + static_cast<long>(i) * ny + j; }
    Eigen::Vector2d position(int i, int j) const { return origin + spacing * Eigen::Vector2d(i, j); }
    std::map<long, Eigen::Vector2d> landmarks() const
    {
        std::map<long, Eigen::Vector2d> out;
        for (int i = 0; i < nx; ++i)
            for (int j = 0; j < ny; ++j) out[id(i, j)] = position(i, j);
        return out;
    }
    /** The two counter-clockwise triangles of every lattice square, nearest centroid
     *  to `centre` first. */
    std::vector<std::array<long, 3>> triangles(const Eigen::Vector2d& centre) const
    {
        std::vector<std::pair<double, std::array<long, 3>>> tris;
        for (int i = 0; i + 1 < nx; ++i)
            for (int j = 0; j + 1 < ny; ++j)
            {
                const Eigen::Vector2d c = position(i, j) + 0.5 * spacing * Eigen::Vector2d(1, 1);
                const Eigen::Vector2d off = spacing * Eigen::Vector2d(1.0 / 6, 1.0 / 6);
                tris.push_back({(c - off - centre).squaredNorm(), {{id(i, j), id(i + 1, j), id(i, j + 1)}}});
                tris.push_back(
                    {(c + off - centre).squaredNorm(), {{id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)}}});
            }
        std::stable_sort(tris.begin(), tris.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        std::vector<std::array<long, 3>> out;
        for (const auto& t : tris) out.push_back(t.second);
        return out;
    }
};

/** Partition options with the correlation conditions off. */
inline hymm::ltr::RegionPartition::Options permissivePartitionOptions()
{
    hymm::ltr::RegionPartition::Options o;
    o.conditions.min_vertex_correlation = 0.0;
    o.conditions.min_vehicle_correlation = 0.0;
    return o;
}

/** Adds the first `count` triangles of `tris`; throws if one is refused. */
inline void addRegions(
    hymm::ltr::RegionPartition& partition, const hymm::ltr::LandmarkCovarianceView& view,
    const std::vector<std::array<long, 3>>& tris, size_t count)
{
    if (count > tris.size()) throw std::invalid_argument("addRegions: not enough triangles");
    for (size_t k = 0; k < count; ++k)
    {
        const auto res = partition.tryAddRegion(tris[k], view, 0.0);
        if (!res.accepted()) throw std::runtime_error("addRegions: refused: " + res.detail);
    }
}

/** DenseCovarianceView of `landmarks` (independent, sigma each) and a vehicle pose. */
inline hymm::ltr::DenseCovarianceView makeDenseView(
    const std::map<long, Eigen::Vector2d>& landmarks, const Eigen::Vector3d& vehicle, double sigma = 0.01)
{
    const int n = 3 + 2 * static_cast<int>(landmarks.size());
    Eigen::VectorXd mean(n);
    mean.head<3>() = vehicle;
    std::map<long, int> offsets;
    int o = 3;
    for (const auto& [id, p] : landmarks)
    {
        offsets[id] = o;
        mean.segment<2>(o) = p;
        o += 2;
    }
    const Eigen::MatrixXd cov = sigma * sigma * Eigen::MatrixXd::Identity(n, n);
    return hymm::ltr::DenseCovarianceView(mean, cov, offsets, 0);
}

}  // namespace hymm::dense::synthetic

#include "hymm/dense/ScanPoints.h"

#include <cmath>

namespace hymm::dense::synthetic
{
/** Scan of the vertical wall x = wall_x seen by a sensor mounted at `mount` on a
 *  vehicle at `vehicle`: `n` beams evenly over [-half_fov, half_fov] (sensor frame),
 *  ranges computed analytically. */
inline ScanPoints wallScan(
    const mrpt::math::TPose2D& vehicle, const mrpt::math::TPose2D& mount, double wall_x, int n,
    double half_fov)
{
    ScanPoints s;
    s.sensor_on_vehicle = mount;
    const mrpt::math::TPose2D sensor = vehicle + mount;
    for (int k = 0; k < n; ++k)
    {
        const double th = -half_fov + 2 * half_fov * k / (n - 1);
        const double phi = sensor.phi + th;
        const double r = (wall_x - sensor.x) / std::cos(phi);
        s.points.emplace_back(r * std::cos(th), r * std::sin(th));
    }
    return s;
}
/** The wall test scene: 5 x 4 landmarks, 5 m apart (24 regions over [0, 20] x [0, 15]),
 *  a vehicle at (3, 7.5) looking at a wall x = kWallX with a kBeams-beam, +-40 deg scan
 *  from a sensor mounted 0.3 m ahead. */
constexpr double kWallX = 17.0;
constexpr int kBeams = 161;
constexpr double kHalfFov = 40.0 * M_PI / 180.0;
inline const mrpt::math::TPose2D kVehicle{3.0, 7.5, 0.0};
inline const mrpt::math::TPose2D kMount{0.3, 0.0, 0.0};

struct WallWorld
{
    Lattice lattice{5, 4, 5.0, Eigen::Vector2d(0, 0)};
    hymm::ltr::DenseCovarianceView view =
        makeDenseView(lattice.landmarks(), Eigen::Vector3d(kVehicle.x, kVehicle.y, kVehicle.phi));
    hymm::ltr::RegionPartition partition{permissivePartitionOptions()};
    WallWorld() { addRegions(partition, view, lattice.triangles(Eigen::Vector2d(10, 7.5)), 24); }
};

}  // namespace hymm::dense::synthetic
