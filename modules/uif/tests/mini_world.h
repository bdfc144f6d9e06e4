/**
 * @file mini_world.h
 * @brief Test/benchmark helper: a small simulated DenseSLAM frame loop around EkfSlam,
 *        RegionPartition and DelayedDenseStore, with ground truth.
 *
 * A vehicle drives along a straight line with a gentle weave through a field of point
 * landmarks (jittered grid) and "dense" points (laser returns of a static scene, drawn at
 * random). Each frame: odometry prediction, range-bearing update with known ids,
 * partition.update on a view of the confirmed landmarks, store.fuse, then the frame's
 * dense returns: those whose estimate lies in a region would go to the dense map
 * directly (counted), the others are offered to the store. Everything is seeded.
 */
#pragma once

#include <hymm/core/RangeBearingModel.h>
#include <hymm/dense/LocalDenseMap.h>
#include <hymm/dense/PointsLayer.h>
#include <hymm/ekf/EkfSlam.h>
#include <hymm/ltr/DenseCovarianceView.h>
#include <hymm/ltr/RegionPartition.h>
#include <hymm/uif/DelayedDenseStore.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <vector>

namespace hymm::uif::testing
{
struct MiniWorldConfig
{
    unsigned seed = 1;
    int landmark_columns = 8;         //!< grid columns, 10 m apart
    double landmark_range_m = 18.0;
    double dense_range_m = 14.0;
    int dense_points = 500;
    double step_m = 1.0;
    double dt = 0.5;                  //!< [s] between frames
    double std_odo_xy = 0.06;
    double std_odo_phi = 0.01;
    double std_lm_range = 0.1;
    double std_lm_bearing = 0.01;
    double std_laser_range = 0.03;
    double std_laser_bearing = 0.004;
    double min_correlation = 0.75;    //!< partition's vertex and vehicle correlation limits
    hymm::uif::DelayedDenseStore::Options store;
};

class MiniWorld
{
public:
    explicit MiniWorld(const MiniWorldConfig& c)
        : cfg_(c), rng_(c.seed), ekf_(hymm::ekf::EkfSlam::Options()),
          partition_(partitionOptions(c)), store_(c.store)
    {
        std::uniform_real_distribution<double> jitter(-2.0, 2.0);
        long id = 0;
        for (int col = 0; col < c.landmark_columns; ++col)
            for (const double y : {-17.0, -8.0, 7.0, 16.0})
                landmarks_[id++] =
                    Eigen::Vector2d(-5.0 + 10.0 * col + jitter(rng_), y + jitter(rng_));
        std::uniform_real_distribution<double> ux(-10.0, 10.0 * c.landmark_columns);
        std::uniform_real_distribution<double> uy(-18.0, 17.0);
        for (int i = 0; i < c.dense_points; ++i) points_.emplace_back(ux(rng_), uy(rng_));
        truth_ = Eigen::Vector3d(-2.0, 0.0, 0.0);
        ekf_.reset(truth_, Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal());
        sensor_ = Eigen::Vector3d(0.4, 0.1, 0.05);
    }

    /** One frame; returns the regions created. */
    std::vector<long> step()
    {
        ++k_;
        t_ += cfg_.dt;
        move();
        observeLandmarks();
        const auto view = makeView();
        const auto created = partition_.update(view, t_);
        const auto sink = [this](long rid, const hymm::dense::RegionScan& rs)
        { localMapFor(rid).insert(rs); };
        const size_t before = fused_.size();
        last_fuse_ = store_.fuse(ekf_, partition_, sink, &fused_);
        for (size_t i = before; i < fused_.size(); ++i) delays_.push_back(t_ - fused_[i].time);
        observeDense();
        return created;
    }

    /** A view of the confirmed point landmarks (what the pipeline's EkfCovarianceView
     *  shows), copied from the filter. */
    hymm::ltr::DenseCovarianceView makeView() const
    {
        std::map<long, int> offsets;
        for (long id : ekf_.landmarkIds())
        {
            const auto& b = ekf_.landmarkBlock(id);
            if (b.dim == 2 && b.confirmed) offsets[id] = static_cast<int>(b.offset);
        }
        return hymm::ltr::DenseCovarianceView(ekf_.mean(), ekf_.cov(), offsets, 0);
    }

    hymm::dense::LocalDenseMap& localMapFor(long rid)
    {
        auto& slot = maps_[rid];
        if (!slot)
        {
            slot = std::make_unique<hymm::dense::LocalDenseMap>(rid, partition_.region(rid).reference);
            slot->addLayer(std::make_unique<hymm::dense::PointsLayer>(hymm::dense::PointsLayer::Options()));
        }
        return *slot;
    }

    const MiniWorldConfig& config() const { return cfg_; }
    hymm::ekf::EkfSlam& ekf() { return ekf_; }
    hymm::ltr::RegionPartition& partition() { return partition_; }
    hymm::uif::DelayedDenseStore& store() { return store_; }
    const std::map<long, Eigen::Vector2d>& landmarks() const { return landmarks_; }
    const std::vector<Eigen::Vector2d>& points() const { return points_; }
    const std::vector<hymm::uif::DelayedDenseStore::FusedPoint>& fused() const { return fused_; }
    const std::map<long, std::unique_ptr<hymm::dense::LocalDenseMap>>& maps() const { return maps_; }
    const hymm::uif::DelayedDenseStore::AddReport& lastAdd() const { return last_add_; }
    const hymm::uif::DelayedDenseStore::FuseReport& lastFuse() const { return last_fuse_; }
    const Eigen::Vector3d& truePose() const { return truth_; }
    const Eigen::Vector3d& sensor() const { return sensor_; }
    size_t directReturns() const { return direct_; }
    /** Per fused return: fusion time minus observation time [s]. */
    const std::vector<double>& fusionDelays() const { return delays_; }
    double time() const { return t_; }

private:
    static hymm::ltr::RegionPartition::Options partitionOptions(const MiniWorldConfig& c)
    {
        hymm::ltr::RegionPartition::Options o;
        o.conditions.min_vertex_correlation = c.min_correlation;
        o.conditions.min_vehicle_correlation = c.min_correlation;
        o.search_radius_m = 20.0;
        return o;
    }

    Eigen::Vector2d gauss2(double s0, double s1)
    {
        std::normal_distribution<double> n(0.0, 1.0);
        return Eigen::Vector2d(s0 * n(rng_), s1 * n(rng_));
    }

    void move()
    {
        std::normal_distribution<double> n(0.0, 1.0);
        const Eigen::Vector3d u(cfg_.step_m, 0.0, 0.04 * std::sin(0.3 * k_));
        truth_ = compose(truth_, u);
        const Eigen::Vector3d meas(u.x() + cfg_.std_odo_xy * n(rng_), u.y() + cfg_.std_odo_xy * n(rng_),
                                   u.z() + cfg_.std_odo_phi * n(rng_));
        Eigen::Matrix3d Q = Eigen::Vector3d(cfg_.std_odo_xy * cfg_.std_odo_xy, cfg_.std_odo_xy * cfg_.std_odo_xy,
                                            cfg_.std_odo_phi * cfg_.std_odo_phi)
                                .asDiagonal();
        mrpt::math::CMatrixDouble33 cov;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) cov(r, c) = Q(r, c);
        ekf_.predictOdometry(mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(meas[0], meas[1], meas[2]), cov));
    }

    static Eigen::Vector3d compose(const Eigen::Vector3d& a, const Eigen::Vector3d& d)
    {
        const double c = std::cos(a.z()), s = std::sin(a.z());
        return Eigen::Vector3d(a.x() + c * d.x() - s * d.y(), a.y() + s * d.x() + c * d.y(),
                               std::remainder(a.z() + d.z(), 2.0 * M_PI));
    }

    void observeLandmarks()
    {
        std::vector<hymm::ekf::RangeBearingObs> obs;
        const Eigen::Matrix2d R =
            Eigen::Vector2d(cfg_.std_lm_range * cfg_.std_lm_range, cfg_.std_lm_bearing * cfg_.std_lm_bearing)
                .asDiagonal();
        for (const auto& [id, p] : landmarks_)
        {
            if ((p - truth_.head<2>()).norm() > cfg_.landmark_range_m) continue;
            hymm::ekf::RangeBearingObs o;
            o.z = hymm::core::observeRangeBearing(truth_, sensor_, p) +
                  gauss2(cfg_.std_lm_range, cfg_.std_lm_bearing);
            o.R = R;
            o.id = id;
            obs.push_back(o);
        }
        ekf_.updateRangeBearing(obs, mrpt::poses::CPose3D(sensor_.x(), sensor_.y(), 0.0, sensor_.z(), 0.0, 0.0));
    }

    void observeDense()
    {
        const Eigen::Matrix2d R = Eigen::Vector2d(cfg_.std_laser_range * cfg_.std_laser_range,
                                                  cfg_.std_laser_bearing * cfg_.std_laser_bearing)
                                      .asDiagonal();
        const Eigen::Vector3d est = ekf_.vehiclePose();
        std::vector<Eigen::Vector2d> z;
        std::vector<long> tags;
        for (size_t i = 0; i < points_.size(); ++i)
        {
            if ((points_[i] - truth_.head<2>()).norm() > cfg_.dense_range_m) continue;
            // Noise is drawn for every return, stored or not, so runs with and without
            // the store see the same random stream.
            const Eigen::Vector2d zi = hymm::core::observeRangeBearing(truth_, sensor_, points_[i]) +
                                       gauss2(cfg_.std_laser_range, cfg_.std_laser_bearing);
            const Eigen::Vector2d g = hymm::core::inverseRangeBearing(est, sensor_, zi);
            if (partition_.findRegion(g))
            {
                ++direct_;
                continue;
            }
            z.push_back(zi);
            tags.push_back(static_cast<long>(i));
        }
        last_add_ = store_.addScan(ekf_, partition_, z, R, sensor_, t_, &tags);
    }

    const MiniWorldConfig cfg_;
    std::mt19937 rng_;
    hymm::ekf::EkfSlam ekf_;
    hymm::ltr::RegionPartition partition_;
    hymm::uif::DelayedDenseStore store_;
    std::map<long, Eigen::Vector2d> landmarks_;
    std::vector<Eigen::Vector2d> points_;
    std::map<long, std::unique_ptr<hymm::dense::LocalDenseMap>> maps_;
    std::vector<hymm::uif::DelayedDenseStore::FusedPoint> fused_;
    hymm::uif::DelayedDenseStore::AddReport last_add_;
    hymm::uif::DelayedDenseStore::FuseReport last_fuse_;
    Eigen::Vector3d truth_;
    Eigen::Vector3d sensor_;
    std::vector<double> delays_;
    size_t direct_ = 0;
    int k_ = 0;
    double t_ = 0;
};

}  // namespace hymm::uif::testing
