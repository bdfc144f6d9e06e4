#include "hymm/eval/se2_alignment.h"

#include <mrpt/math/wrap2pi.h>

#include <cmath>

namespace hymm::eval
{
Eigen::Matrix2d Se2Transform::rotation() const
{
    const double c = std::cos(phi), s = std::sin(phi);
    Eigen::Matrix2d R;
    R << c, -s, s, c;
    return R;
}

Eigen::Vector2d Se2Transform::apply(const Eigen::Vector2d& p) const
{
    return rotation() * p + Eigen::Vector2d(x, y);
}

double Se2Transform::applyHeading(double heading) const
{
    return mrpt::math::wrapToPi(heading + phi);
}

Se2Transform Se2Transform::inverse() const
{
    const Eigen::Vector2d t = -(rotation().transpose() * Eigen::Vector2d(x, y));
    return Se2Transform{t.x(), t.y(), mrpt::math::wrapToPi(-phi)};
}

std::optional<Se2Transform> alignSE2(
    const std::vector<Eigen::Vector2d>& source, const std::vector<Eigen::Vector2d>& target)
{
    const size_t n = source.size();
    if (n < 2 || target.size() != n) return std::nullopt;
    Eigen::Vector2d ms = Eigen::Vector2d::Zero(), md = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < n; ++i) ms += source[i], md += target[i];
    ms /= static_cast<double>(n);
    md /= static_cast<double>(n);

    double dot = 0, cross = 0, spread = 0, scale = 0;
    for (size_t i = 0; i < n; ++i)
    {
        const Eigen::Vector2d s = source[i] - ms, d = target[i] - md;
        dot += s.dot(d);
        cross += s.x() * d.y() - s.y() * d.x();
        spread += s.squaredNorm();
        scale += source[i].squaredNorm();
    }
    // All source points coincide: any rotation fits equally well.
    if (!(spread > 1e-20 * std::max(scale, 1.0))) return std::nullopt;
    if (dot == 0 && cross == 0) return std::nullopt;

    Se2Transform T;
    T.phi = std::atan2(cross, dot);
    const Eigen::Vector2d t = md - T.rotation() * ms;
    T.x = t.x();
    T.y = t.y();
    return T;
}

std::optional<Eigen::RowVectorXd> alignSE2RotationJacobian(
    const std::vector<Eigen::Vector2d>& source, const std::vector<Eigen::Vector2d>& target)
{
    if (!alignSE2(source, target)) return std::nullopt;
    const size_t n = source.size();
    Eigen::Vector2d ms = Eigen::Vector2d::Zero(), md = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < n; ++i) ms += source[i], md += target[i];
    ms /= static_cast<double>(n);
    md /= static_cast<double>(n);
    double dot = 0, cross = 0;
    for (size_t i = 0; i < n; ++i)
    {
        const Eigen::Vector2d s = source[i] - ms, d = target[i] - md;
        dot += s.dot(d);
        cross += s.x() * d.y() - s.y() * d.x();
    }
    // phi = atan2(cross, dot). The centred targets sum to zero, so moving source point i
    // changes cross by (d_y, -d_x) and dot by (d_x, d_y) per unit step, the shift of the
    // source mean dropping out.
    const double k = 1.0 / (dot * dot + cross * cross);
    Eigen::RowVectorXd J(2 * n);
    for (size_t i = 0; i < n; ++i)
    {
        const Eigen::Vector2d d = target[i] - md;
        J(2 * i) = k * (dot * d.y() - cross * d.x());
        J(2 * i + 1) = k * (-dot * d.x() - cross * d.y());
    }
    return J;
}

}  // namespace hymm::eval
