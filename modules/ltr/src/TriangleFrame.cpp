/**
 * @file TriangleFrame.cpp
 * @brief Local coordinates of an LTR and their Jacobians (Eq. 3.6-3.9, App. C).
 */
#include "hymm/ltr/TriangleFrame.h"

#include <Eigen/SVD>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hymm::ltr
{
namespace
{
Eigen::Matrix2d axesOf(const TriangleFrame::Vertices& v)
{
    Eigen::Matrix2d d;
    d.col(0) = v[1] - v[0];
    d.col(1) = v[2] - v[0];
    return d;
}
}  // namespace

std::string TriangleFrame::degeneracyReason(const Vertices& v, const FrameLimits& limits)
{
    for (const auto& p : v)
        if (!p.allFinite()) return "a vertex is not finite";
    const Eigen::Matrix2d d = axesOf(v);
    const double area = 0.5 * std::abs(d.determinant());
    std::ostringstream os;
    if (!(area >= limits.min_area))
    {
        os << "triangle area " << area << " m^2 is below the minimum " << limits.min_area
           << " m^2";
        return os.str();
    }
    // The condition number of D bounds how much relative error in the vertices is
    // amplified into the local coordinates; a sliver triangle has a huge one even
    // when its area is acceptable.
    const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix2d>(d).singularValues();
    if (!(s(1) > 0) || !(s(0) / s(1) <= limits.max_condition_number))
    {
        os << "triangle axes condition number " << (s(1) > 0 ? s(0) / s(1) : INFINITY)
           << " exceeds the maximum " << limits.max_condition_number;
        return os.str();
    }
    return {};
}

TriangleFrame::TriangleFrame(const Vertices& v, Unchecked) : v_(v), d_(axesOf(v))
{
    d_inv_ = d_.inverse();
}

TriangleFrame::TriangleFrame(
    const Eigen::Vector2d& l1, const Eigen::Vector2d& l2, const Eigen::Vector2d& l3,
    const FrameLimits& limits)
    : TriangleFrame(Vertices{l1, l2, l3}, Unchecked{})
{
    const std::string why = degeneracyReason(v_, limits);
    if (!why.empty()) throw std::invalid_argument("TriangleFrame: degenerate triangle: " + why);
}

std::optional<TriangleFrame> TriangleFrame::tryCreate(
    const Vertices& v, const FrameLimits& limits, std::string* why)
{
    std::string reason = degeneracyReason(v, limits);
    if (!reason.empty())
    {
        if (why) *why = std::move(reason);
        return std::nullopt;
    }
    return TriangleFrame(v, Unchecked{});
}

double TriangleFrame::area() const { return std::abs(signedArea()); }

Eigen::Vector2d TriangleFrame::toLocal(const Eigen::Vector2d& x) const
{
    return d_inv_ * (x - v_[0]);
}

Eigen::Vector2d TriangleFrame::toGlobal(const Eigen::Vector2d& local) const
{
    return v_[0] + d_ * local;
}

Eigen::Vector3d TriangleFrame::weights(const Eigen::Vector2d& local)
{
    return {1.0 - local.x() - local.y(), local.x(), local.y()};
}

bool TriangleFrame::insideLocal(const Eigen::Vector2d& local, double tol)
{
    return local.x() >= -tol && local.y() >= -tol && local.x() + local.y() <= 1.0 + tol;
}

Eigen::Matrix2d TriangleFrame::jacLocalWrtVertex(const Eigen::Vector2d& x, int k) const
{
    if (k < 0 || k > 2) throw std::out_of_range("TriangleFrame: vertex index must be 0, 1 or 2");
    return -weights(toLocal(x))(k) * d_inv_;
}

Eigen::Matrix<double, 2, 6> TriangleFrame::jacLocalWrtVertices(const Eigen::Vector2d& x) const
{
    const Eigen::Vector3d w = weights(toLocal(x));
    Eigen::Matrix<double, 2, 6> j;
    for (int k = 0; k < 3; ++k) j.block<2, 2>(0, 2 * k) = -w(k) * d_inv_;
    return j;
}

Eigen::Matrix2d TriangleFrame::jacGlobalWrtVertex(const Eigen::Vector2d& local, int k)
{
    if (k < 0 || k > 2) throw std::out_of_range("TriangleFrame: vertex index must be 0, 1 or 2");
    return weights(local)(k) * Eigen::Matrix2d::Identity();
}

Eigen::Matrix<double, 2, 6> TriangleFrame::jacGlobalWrtVertices(const Eigen::Vector2d& local)
{
    const Eigen::Vector3d w = weights(local);
    Eigen::Matrix<double, 2, 6> j;
    for (int k = 0; k < 3; ++k) j.block<2, 2>(0, 2 * k) = w(k) * Eigen::Matrix2d::Identity();
    return j;
}

}  // namespace hymm::ltr
