/**
 * @file quadratic_fit.cpp
 * @brief Thesis 5.4: covariance of a likelihood from its values near the maximum.
 */
#include "hymm/scanslam/quadratic_fit.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace hymm::scanslam
{
std::optional<Mat3> fitInverseCovariance(const std::vector<Vec3>& d, const std::vector<double>& c)
{
    if (d.size() != c.size() || d.size() < 6) return std::nullopt;
    Eigen::MatrixXd a(d.size(), 6);
    Eigen::VectorXd b(d.size());
    for (size_t i = 0; i < d.size(); ++i)
    {
        const double x = d[i].x(), y = d[i].y(), z = d[i].z();
        a.row(static_cast<Eigen::Index>(i)) << x * x, 2 * x * y, 2 * x * z, y * y, 2 * y * z, z * z;
        b(static_cast<Eigen::Index>(i)) = c[i];
    }
    // Columns differ by orders of magnitude (metres vs radians): scale them before the
    // SVD so the rank decision is about geometry, not units.
    Eigen::VectorXd scale = a.colwise().norm().transpose();
    for (Eigen::Index k = 0; k < 6; ++k)
    {
        if (scale(k) <= 0) return std::nullopt;
        a.col(k) /= scale(k);
    }
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
    svd.setThreshold(1e-9);
    if (svd.rank() < 6) return std::nullopt;
    Eigen::VectorXd u = svd.solve(b);
    u = u.cwiseQuotient(scale);
    Mat3 inv;
    inv << u(0), u(1), u(2), u(1), u(3), u(4), u(2), u(4), u(5);
    Eigen::SelfAdjointEigenSolver<Mat3> es(inv);
    if (es.eigenvalues().minCoeff() <= 0) return std::nullopt;
    return inv;
}

std::vector<Vec3> quadraticFitStencil(const Vec3& step)
{
    std::vector<Vec3> out;
    for (int k = 0; k < 3; ++k)
        for (double sg : {-1.0, 1.0})
        {
            Vec3 v = Vec3::Zero();
            v(k) = sg * step(k);
            out.push_back(v);
        }
    for (int k = 0; k < 3; ++k)
        for (int l = k + 1; l < 3; ++l)
            for (double sk : {-1.0, 1.0})
                for (double sl : {-1.0, 1.0})
                {
                    Vec3 v = Vec3::Zero();
                    v(k) = sk * step(k);
                    v(l) = sl * step(l);
                    out.push_back(v);
                }
    return out;
}

}  // namespace hymm::scanslam
