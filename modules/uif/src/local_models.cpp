/**
 * @file local_models.cpp
 * @brief Eq. 3.27-3.29 and their Jacobians (derivations in local_models.h).
 */
#include "hymm/uif/local_models.h"

#include <hymm/core/RangeBearingModel.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>

namespace hymm::uif
{
namespace
{
/** Heading theta_a of the first axis a = L2 - L1 and its gradient d theta_a / d a. */
double axisHeading(const hymm::ltr::TriangleFrame& frame, Eigen::RowVector2d* grad)
{
    const Vec2 a = frame.axes().col(0);
    if (grad)
    {
        // d atan2(a_y, a_x) = (-a_y, a_x) / |a|^2; |a| > 0 for any valid frame.
        *grad = Eigen::RowVector2d(-a.y(), a.x()) / a.squaredNorm();
    }
    return std::atan2(a.y(), a.x());
}
}  // namespace

Vec3 localVehiclePose(
    const Vec3& pose, const hymm::ltr::TriangleFrame& frame, Mat3* J_pose, Mat36* J_vertices)
{
    Eigen::RowVector2d g;
    const double theta_a = axisHeading(frame, &g);
    const Vec2 l = frame.toLocal(pose.head<2>());
    Vec3 out(l.x(), l.y(), mrpt::math::wrapToPi(pose.z() - theta_a));  // Eq. 3.28 (atan2)
    if (J_pose)
    {
        J_pose->setZero();
        J_pose->topLeftCorner<2, 2>() = frame.jacLocalWrtPoint();
        (*J_pose)(2, 2) = 1.0;
    }
    if (J_vertices)
    {
        J_vertices->topRows<2>() = frame.jacLocalWrtVertices(pose.head<2>());
        // gamma = phi - theta_a(L2 - L1): d gamma / dL1 = +g, d gamma / dL2 = -g.
        J_vertices->row(2) << g, -g, 0.0, 0.0;
    }
    return out;
}

Vec3 globalVehiclePose(const Vec3& local_pose, const hymm::ltr::TriangleFrame& frame)
{
    const Vec2 p = frame.toGlobal(local_pose.head<2>());
    const double theta_a = axisHeading(frame, nullptr);
    return Vec3(p.x(), p.y(), mrpt::math::wrapToPi(local_pose.z() + theta_a));
}

Vec2 pointLocal(
    const Vec3& pose, const Vec3& sensor, const Vec2& z, const hymm::ltr::TriangleFrame& frame,
    PointLocalJacobians* J)
{
    Mat23 G_v;
    Mat2 G_z;
    const Vec2 g = hymm::core::inverseRangeBearing(pose, sensor, z, J ? &G_v : nullptr, J ? &G_z : nullptr);
    if (J)
    {
        // l = D^{-1} (g - L1): chain rule through g (App. C C.5) and the vertices (C.7-C.9).
        J->pose = frame.jacLocalWrtPoint() * G_v;
        J->z = frame.jacLocalWrtPoint() * G_z;
        J->vertices = frame.jacLocalWrtVertices(g);
    }
    return frame.toLocal(g);
}

Vec2 pointLocalFromLocalPose(
    const Vec3& local_pose, const Vec3& sensor, const Vec2& z, const hymm::ltr::TriangleFrame& frame,
    PointFromLocalPoseJacobians* J)
{
    // x_v = (L1 + D [alpha, beta], gamma + theta_a), then l = pointLocal(x_v, z).
    const Vec3 pose = globalVehiclePose(local_pose, frame);
    PointLocalJacobians Jg;
    const Vec2 l = pointLocal(pose, sensor, z, frame, J ? &Jg : nullptr);
    if (J)
    {
        Eigen::RowVector2d g;
        axisHeading(frame, &g);
        // d x_v / d x_v^L = blockdiag(D, 1).
        Mat3 dpose_dlocal = Mat3::Zero();
        dpose_dlocal.topLeftCorner<2, 2>() = frame.axes();
        dpose_dlocal(2, 2) = 1.0;
        J->local_pose = Jg.pose * dpose_dlocal;
        J->z = Jg.z;
        // d x_v / d L at fixed local pose: position moves with weights (1-a-b, a, b),
        // heading with theta_a (dL1: -g, dL2: +g).
        const Vec3 w = hymm::ltr::TriangleFrame::weights(local_pose.head<2>());
        Mat36 dpose_dL = Mat36::Zero();
        for (int k = 0; k < 3; ++k) dpose_dL.block<2, 2>(0, 2 * k) = w[k] * Mat2::Identity();
        dpose_dL.block<1, 2>(2, 0) = -g;
        dpose_dL.block<1, 2>(2, 2) = g;
        J->vertices = Jg.pose * dpose_dL + Jg.vertices;
    }
    return l;
}

}  // namespace hymm::uif
