/**
 * @file position_error.cpp
 */
#include "hymm/ltr/position_error.h"

namespace hymm::ltr
{
Eigen::Matrix<double, 6, 6> jointVertexCovariance(
    const LandmarkCovarianceView& view, const std::array<long, 3>& ids)
{
    Eigen::Matrix<double, 6, 6> p;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            p.block<2, 2>(2 * i, 2 * j) =
                i == j ? view.cov(ids[static_cast<size_t>(i)])
                       : view.crossCov(ids[static_cast<size_t>(i)], ids[static_cast<size_t>(j)]);
    return p;
}

Eigen::Matrix2d globalPositionCovariance(
    const TriangleFrame& frame, const Eigen::Vector2d& local,
    const Eigen::Matrix<double, 6, 6>& vertex_cov, const Eigen::Matrix2d& local_cov)
{
    const Eigen::Matrix<double, 2, 6> jl = TriangleFrame::jacGlobalWrtVertices(local);
    const Eigen::Matrix2d jd = frame.jacGlobalWrtLocal();
    const Eigen::Matrix2d p = jl * vertex_cov * jl.transpose() + jd * local_cov * jd.transpose();
    return 0.5 * (p + p.transpose());
}

Eigen::Matrix2d globalPositionCovariance(
    const LandmarkCovarianceView& view, const std::array<long, 3>& ids,
    const Eigen::Vector2d& local, const Eigen::Matrix2d& local_cov)
{
    const TriangleFrame frame(view.mean(ids[0]), view.mean(ids[1]), view.mean(ids[2]));
    return globalPositionCovariance(frame, local, jointVertexCovariance(view, ids), local_cov);
}

Eigen::Vector2d globalDisplacement(
    const Eigen::Vector2d& local, const std::array<Eigen::Vector2d, 3>& delta)
{
    const Eigen::Vector3d w = TriangleFrame::weights(local);
    return w(0) * delta[0] + w(1) * delta[1] + w(2) * delta[2];
}

Eigen::Matrix2d localCoordinatesCovariance(
    const TriangleFrame& frame, const Eigen::Vector2d& x, const Eigen::Matrix2d& p_xx,
    const Eigen::Matrix<double, 2, 6>& p_xl, const Eigen::Matrix<double, 6, 6>& vertex_cov)
{
    const Eigen::Matrix2d jx = frame.jacLocalWrtPoint();
    const Eigen::Matrix<double, 2, 6> jl = frame.jacLocalWrtVertices(x);
    const Eigen::Matrix2d cross = jx * p_xl * jl.transpose();
    const Eigen::Matrix2d p = jx * p_xx * jx.transpose() + jl * vertex_cov * jl.transpose() +
                              cross + cross.transpose();
    return 0.5 * (p + p.transpose());
}

Eigen::Matrix2d localFusionCovariance(
    const LandmarkCovarianceView& view, const std::array<long, 3>& ids, const Eigen::Vector2d& x)
{
    const TriangleFrame frame(view.mean(ids[0]), view.mean(ids[1]), view.mean(ids[2]));
    const Eigen::Vector3d v = view.vehiclePose();
    Eigen::Matrix<double, 2, 3> g;
    g << 1, 0, -(x.y() - v.y()), 0, 1, x.x() - v.x();
    const Eigen::Matrix2d p_xx = g * view.vehicleCov() * g.transpose();
    Eigen::Matrix<double, 2, 6> p_xl;
    for (int k = 0; k < 3; ++k)
        p_xl.block<2, 2>(0, 2 * k) = g * view.crossVehicle(ids[static_cast<size_t>(k)]).transpose();
    const Eigen::Matrix2d p_l =
        localCoordinatesCovariance(frame, x, p_xx, p_xl, jointVertexCovariance(view, ids));
    const Eigen::Matrix2d p = frame.axes() * p_l * frame.axes().transpose();
    return 0.5 * (p + p.transpose());
}

}  // namespace hymm::ltr
