#include "hymm/eval/se2_alignment.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>
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

namespace
{
/** Centroids and the centred sums sum s' . d' and sum s' x d' that fix the rotation. */
struct CentredSums
{
    Eigen::Vector2d source_mean, target_mean;
    double dot = 0, cross = 0;
};

std::optional<CentredSums> centredSums(const std::vector<Eigen::Vector2d>& source,
                                       const std::vector<Eigen::Vector2d>& target)
{
    const size_t n = source.size();
    if (n < 2 || target.size() != n) return std::nullopt;
    CentredSums c;
    c.source_mean = c.target_mean = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < n; ++i) c.source_mean += source[i], c.target_mean += target[i];
    c.source_mean /= static_cast<double>(n);
    c.target_mean /= static_cast<double>(n);

    double spread = 0, scale = 0;
    for (size_t i = 0; i < n; ++i)
    {
        const Eigen::Vector2d s = source[i] - c.source_mean, d = target[i] - c.target_mean;
        c.dot += s.dot(d);
        c.cross += s.x() * d.y() - s.y() * d.x();
        spread += s.squaredNorm();
        scale += source[i].squaredNorm();
    }
    // All source points coincide: any rotation fits equally well.
    if (!(spread > 1e-20 * std::max(scale, 1.0))) return std::nullopt;
    if (c.dot == 0 && c.cross == 0) return std::nullopt;
    return c;
}
}  // namespace

std::optional<Se2Transform> alignSE2(
    const std::vector<Eigen::Vector2d>& source, const std::vector<Eigen::Vector2d>& target)
{
    const auto c = centredSums(source, target);
    if (!c) return std::nullopt;
    Se2Transform T;
    T.phi = std::atan2(c->cross, c->dot);
    const Eigen::Vector2d t = c->target_mean - T.rotation() * c->source_mean;
    T.x = t.x();
    T.y = t.y();
    return T;
}

std::optional<Eigen::RowVectorXd> alignSE2RotationJacobian(
    const std::vector<Eigen::Vector2d>& source, const std::vector<Eigen::Vector2d>& target)
{
    const auto c = centredSums(source, target);
    if (!c) return std::nullopt;
    // phi = atan2(cross, dot). The centred targets sum to zero, so moving source point i
    // changes cross by (d_y, -d_x) and dot by (d_x, d_y) per unit step, the shift of the
    // source mean dropping out.
    const double k = 1.0 / (c->dot * c->dot + c->cross * c->cross);
    Eigen::RowVectorXd J(2 * source.size());
    for (size_t i = 0; i < source.size(); ++i)
    {
        const Eigen::Vector2d d = target[i] - c->target_mean;
        J(2 * i) = k * (c->dot * d.y() - c->cross * d.x());
        J(2 * i + 1) = k * (-c->dot * d.x() - c->cross * d.y());
    }
    return J;
}

}  // namespace hymm::eval
