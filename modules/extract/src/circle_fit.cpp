#include "hymm/extract/circle_fit.h"

#include <Eigen/Dense>

#include <cmath>

namespace hymm::extract
{
namespace
{
// Gauss-Newton on the geometric residuals converges in a handful of iterations from the
// algebraic solution; these bound the work on pathological input.
constexpr int kMaxGaussNewtonIterations = 20;
constexpr int kMaxStepHalvings = 10;

double sumSquaredResiduals(
    const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& c, double r)
{
    double s = 0;
    for (const auto& p : points)
    {
        const double e = (p - c).norm() - r;
        s += e * e;
    }
    return s;
}

bool allFinite(const std::vector<Eigen::Vector2d>& points)
{
    for (const auto& p : points)
        if (!p.allFinite()) return false;
    return true;
}

// Refines (centre, radius) in place; keeps the input if no step reduces the cost.
void refineGeometric(const std::vector<Eigen::Vector2d>& points, Eigen::Vector2d& c, double& r)
{
    double cost = sumSquaredResiduals(points, c, r);
    for (int it = 0; it < kMaxGaussNewtonIterations; ++it)
    {
        Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
        Eigen::Vector3d Jte = Eigen::Vector3d::Zero();
        for (const auto& p : points)
        {
            const Eigen::Vector2d d = p - c;
            const double n = d.norm();
            if (n <= 0) return;  // a point on the centre: the residual is not differentiable
            const Eigen::Vector3d J(-d.x() / n, -d.y() / n, -1.0);
            const double e = n - r;
            JtJ += J * J.transpose();
            Jte += J * e;
        }
        const Eigen::Vector3d delta = JtJ.ldlt().solve(-Jte);
        if (!delta.allFinite()) return;

        double step = 1.0;
        bool improved = false;
        for (int h = 0; h < kMaxStepHalvings; ++h, step *= 0.5)
        {
            const Eigen::Vector2d c_new = c + step * delta.head<2>();
            const double r_new = r + step * delta[2];
            const double cost_new = sumSquaredResiduals(points, c_new, r_new);
            if (r_new > 0 && cost_new < cost)
            {
                c = c_new;
                r = r_new;
                const double rel_change = (cost - cost_new) / std::max(cost, 1e-300);
                cost = cost_new;
                improved = rel_change > 1e-12;
                break;
            }
        }
        if (!improved) return;
    }
}
}  // namespace

double circleRms(
    const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& centre, double radius)
{
    if (points.empty()) return 0;
    return std::sqrt(sumSquaredResiduals(points, centre, radius) / points.size());
}

std::optional<Circle> fitCircle(const std::vector<Eigen::Vector2d>& points, double min_rcond)
{
    const size_t n = points.size();
    if (n < 3 || !allFinite(points)) return std::nullopt;

    // Algebraic (Kasa) fit on centred coordinates: with sum(u) = 0 the normal equations
    // of x^2 + y^2 + A x + B y + C = 0 decouple into the 2x2 scatter matrix for (A, B)
    // and C = -mean(|u|^2). Centring keeps the system well scaled far from the sensor.
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : points) mean += p;
    mean /= static_cast<double>(n);

    Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
    Eigen::Vector2d b = Eigen::Vector2d::Zero();
    double sum_sq = 0;
    for (const auto& p : points)
    {
        const Eigen::Vector2d u = p - mean;
        const double q = u.squaredNorm();
        S += u * u.transpose();
        b -= u * q;
        sum_sq += q;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(S);
    const double lmax = eig.eigenvalues()[1], lmin = eig.eigenvalues()[0];
    if (!(lmax > 0) || lmin / lmax < min_rcond) return std::nullopt;  // collinear

    const Eigen::Vector2d AB = S.ldlt().solve(b);
    const double C = -sum_sq / static_cast<double>(n);
    const double r2 = AB.squaredNorm() / 4.0 - C;
    if (!AB.allFinite() || !(r2 > 0)) return std::nullopt;

    Circle c;
    c.centre = mean - AB / 2.0;
    c.radius = std::sqrt(r2);
    refineGeometric(points, c.centre, c.radius);
    c.rms = circleRms(points, c.centre, c.radius);
    if (!c.centre.allFinite() || !std::isfinite(c.radius)) return std::nullopt;
    return c;
}

}  // namespace hymm::extract
