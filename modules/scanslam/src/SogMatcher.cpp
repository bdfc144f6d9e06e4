/**
 * @file SogMatcher.cpp
 * @brief Sum-of-Gaussians scan correlation and its covariance (thesis 5.3.1, 5.4).
 */
#include "hymm/scanslam/SogMatcher.h"

#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <optional>

#include "hymm/core/config_utils.h"
#include "hymm/scanslam/quadratic_fit.h"

namespace hymm::scanslam
{
SogMatcher::SogMatcher() : options_() {}

hymm::core::OptionTable SogMatcher::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.choice("objective", objective, {{"product", Objective::product}, {"sum", Objective::sum}},
             "`product` (per-point mixtures) or `sum` (Eq. 5.13 literally)");
    t.reals("scales_m", scales_m, "m", atLeast(0, 100), 1, "smoothing std added per level, coarse to fine; the last level gives the covariance");
    t.integer("max_iterations", max_iterations, "", 1, 100000, "Newton steps per level");
    t.real("gate_sigma", gate_sigma, "sigma", above(0, 1000), "pairs beyond this Mahalanobis distance are left out");
    t.real("min_matched_fraction", min_matched_fraction, "", between(0, 1),
           "template points with a scan point within 3 sigma, else `too_few_matches`");
    t.real("max_correction_m", max_correction_m, "m", above(0, 10000),
           "a result further than this from the initial guess is `diverged`");
    t.real("max_correction_deg", max_correction, "deg", above(0, 360), "same for the angle",
           M_PI / 180);
    t.real("cov_inflation", cov_inflation, "", above(0, 1000), "covariance multiplier (measured, see above)");
    return t;
}

void SogMatcher::Options::load(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    table().load(cfg, section);
}

namespace
{
/** One template point's part of Eq. 5.13: the sum over the scan points of gamma_ij, with
 *  its gradient and Hessian in z when asked for. */
struct PointTerm
{
    double li = 0;
    Vec3 gi = Vec3::Zero();
    Mat3 hi = Mat3::Zero();
    bool matched = false;  // a pair within 3 sigma
};

/** PointTerm of the template point whose rotated position is rp (moved by z) and rotated
 *  covariance pi, with the smoothing variance extra_var on every pair. */
PointTerm pointTerm(const PointSet& scan, const Vec2& rp, const Vec3& z, const Mat2& pi, double extra_var,
                    double gate2, bool derivatives)
{
    PointTerm t;
    const Vec2 tp = rp + z.head<2>();
    const double tr_p = pi.trace() + 2 * extra_var;
    const Vec2 a(-rp.y(), rp.x());  // d(R p)/dphi
    for (size_t j = 0; j < scan.size(); ++j)
    {
        const Vec2 d = tp - scan.points[j];
        const double d2 = d.squaredNorm();
        // |d|^2 <= gate^2 * lambda_max(Sigma) <= gate^2 * trace(Sigma) for any pair
        // within the Mahalanobis gate.
        if (d2 > gate2 * (tr_p + scan.covs[j].trace())) continue;
        Mat2 sig = pi + scan.covs[j];
        sig(0, 0) += extra_var;
        sig(1, 1) += extra_var;
        const double det = sig.determinant();
        if (!(det > 0)) continue;
        const Mat2 inv = sig.inverse();
        const Vec2 u = inv * d;
        const double m2 = d.dot(u);
        if (m2 > gate2) continue;
        if (m2 < 9) t.matched = true;
        // gamma_ij of Eq. 5.13: a Gaussian in d with covariance P_i + Q_j.
        const double f = std::exp(-0.5 * m2) / (2 * M_PI * std::sqrt(det));
        t.li += f;
        if (!derivatives) continue;
        // d = R p + t - q: dd/dz = [I | a], d2d/dphi2 = -R p.
        const Vec3 jtu(u.x(), u.y(), a.dot(u));
        Eigen::Matrix<double, 2, 3> jm;
        jm << 1, 0, a.x(), 0, 1, a.y();
        t.gi -= f * jtu;
        Mat3 hh = f * (jtu * jtu.transpose()) - f * (jm.transpose() * inv * jm);
        hh(2, 2) += f * u.dot(rp);
        t.hi += hh;
    }
    return t;
}
}  // namespace

SogMatcher::Evaluation SogMatcher::evaluate(const PointSet& tpl, const PointSet& scan,
                                            const Vec3& z, double extra_var, double cov_phi,
                                            bool derivatives) const
{
    Evaluation ev;
    const double c = std::cos(z.z()), s = std::sin(z.z());
    const Mat2 rc = rotation(cov_phi);
    const double gate2 = options_.gate_sigma * options_.gate_sigma;
    const bool product = options_.objective == Objective::product;
    double total = 0;          // sum objective: Lambda of Eq. 5.13
    double log_sum = 0;        // product objective: sum_i ln Lambda_i
    Vec3 g_total = Vec3::Zero();
    Mat3 h_total = Mat3::Zero();
    Vec3 g_prod = Vec3::Zero();
    Mat3 h_prod = Mat3::Zero();
    for (size_t i = 0; i < tpl.size(); ++i)
    {
        const Vec2& p = tpl.points[i];
        const Vec2 rp(c * p.x() - s * p.y(), s * p.x() + c * p.y());
        const Mat2 pi = rc * tpl.covs[i] * rc.transpose();
        const PointTerm t = pointTerm(scan, rp, z, pi, extra_var, gate2, derivatives);
        const double li = t.li;
        if (t.matched) ++ev.matched;
        total += li;
        g_total += t.gi;
        h_total += t.hi;
        if (!product) continue;
        // A point with no scan point within the gate contributes the constant floor:
        // the value of one pair at the gate distance (an outlier-robust kernel).
        const double floor_i =
            std::exp(-0.5 * gate2) / (2 * M_PI * std::sqrt((pi + Mat2::Identity() * extra_var).determinant() + 1e-300));
        if (li > floor_i)
        {
            log_sum += std::log(li);
            if (derivatives)
            {
                const Vec3 g = t.gi / li;
                g_prod += g;
                h_prod += t.hi / li - g * g.transpose();
            }
        }
        else
            log_sum += std::log(floor_i);
    }
    if (!(total > 0)) return ev;
    if (product)
    {
        ev.log_l = log_sum;
        ev.gradient = g_prod;
        ev.hessian = h_prod;
        return ev;
    }
    ev.log_l = std::log(total);
    if (derivatives)
    {
        ev.gradient = g_total / total;
        ev.hessian = h_total / total - ev.gradient * ev.gradient.transpose();
    }
    return ev;
}

namespace
{
/** The scan points that can reach the template around z0 at some smoothing level. */
PointSet reachablePoints(const PointSet& tpl, const PointSet& scan, const Vec3& z0, const SogMatcher::Options& o)
{
    double radius = 0;
    for (const Vec2& p : tpl.points) radius = std::max(radius, p.norm());
    double smax = 0;
    for (double s : o.scales_m) smax = std::max(smax, s);
    const double reach = radius + 2.0 + o.gate_sigma * (smax + 1.0);
    PointSet near;
    for (size_t j = 0; j < scan.size(); ++j)
        if ((scan.points[j] - z0.head<2>()).norm() < reach) near.add(scan.points[j], scan.covs[j]);
    return near;
}

/** Levenberg-Marquardt ascent of the objective at one smoothing variance `ev`, from `z`
 *  with its evaluation `cur` (both updated); counts the steps in res.iterations. */
void ascendLevel(const SogMatcher& m, const PointSet& tpl, const PointSet& near, double ev, Vec3& z,
                 SogMatcher::Evaluation& cur, AlignResult& res)
{
    double lambda = 1e-3;
    for (int it = 0; it < m.options().max_iterations; ++it)
    {
        ++res.iterations;
        Mat3 a = -cur.hessian;
        for (int k = 0; k < 3; ++k) a(k, k) += lambda * std::max(std::abs(a(k, k)), 1e-9);
        Eigen::LDLT<Mat3> ldlt(a);
        if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
            ldlt.vectorD().minCoeff() <= 0)
        {
            lambda *= 10;
            if (lambda > 1e10) break;
            continue;
        }
        const Vec3 step = ldlt.solve(cur.gradient);
        Vec3 zn = z + step;
        zn.z() = mrpt::math::wrapToPi(zn.z());
        const SogMatcher::Evaluation nxt = m.evaluate(tpl, near, zn, ev, zn.z(), true);
        if (std::isfinite(nxt.log_l) && nxt.log_l >= cur.log_l)
        {
            z = zn;
            cur = nxt;
            lambda = std::max(lambda * 0.1, 1e-9);
            if (step.head<2>().norm() < 1e-6 && std::abs(step.z()) < 1e-7) break;
        }
        else
        {
            lambda *= 10;
            if (lambda > 1e10) break;
        }
    }
}

/** Thesis 5.4: samples the likelihood (last level's smoothing) around the maximum `z` at
 *  about one conditional sigma per axis and fits P^-1 by least squares; falls back to the
 *  curvature at the maximum. nullopt if neither is positive definite. */
std::optional<Mat3> sampledCovariance(const SogMatcher& m, const PointSet& tpl, const PointSet& near,
                                      const Vec3& z, const SogMatcher::Evaluation& cur)
{
    const auto& scales = m.options().scales_m;
    const double ev_last = scales.back() * scales.back();
    Vec3 step;
    for (int k = 0; k < 3; ++k)
    {
        const double curv = -cur.hessian(k, k);
        step(k) = curv > 0 ? 1.0 / std::sqrt(curv) : (k < 2 ? 0.1 : 0.01);
    }
    step.x() = std::clamp(step.x(), 1e-4, 0.5);
    step.y() = std::clamp(step.y(), 1e-4, 0.5);
    step.z() = std::clamp(step.z(), 1e-5, 0.2);
    std::vector<Vec3> offsets = quadraticFitStencil(step);
    std::vector<double> values;
    values.reserve(offsets.size());
    for (const Vec3& d : offsets)
    {
        const Vec3 zs = z + d;
        const double l = m.evaluate(tpl, near, zs, ev_last, zs.z(), false).log_l;
        values.push_back(std::isfinite(l) ? -2.0 * (l - cur.log_l) : 1e6);
    }
    const auto inv = fitInverseCovariance(offsets, values);
    if (inv) return Mat3(inv->inverse());
    // Fall back to the curvature at the maximum when the fit is not positive
    // definite (a likelihood far from Gaussian within one sigma).
    Eigen::LDLT<Mat3> ldlt(-cur.hessian);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return std::nullopt;
    return Mat3(ldlt.solve(Mat3::Identity()));
}
}  // namespace

AlignResult SogMatcher::align(const PointSet& tpl, const PointSet& scan, const Vec3& z0) const
{
    if (auto bad = rejectInput(tpl, scan, z0)) return *bad;
    AlignResult res;
    res.z = z0;
    // Only scan points that can reach the template at some level take part.
    const PointSet near = reachablePoints(tpl, scan, z0, options_);
    if (near.size() < 3)
    {
        res.failure = "too_few_points";
        return res;
    }

    Vec3 z = z0;
    Evaluation cur;
    for (double scale : options_.scales_m)
    {
        const double ev = scale * scale;
        cur = evaluate(tpl, near, z, ev, z.z(), true);
        if (!std::isfinite(cur.log_l))
        {
            res.failure = "no_overlap";
            return res;
        }
        ascendLevel(*this, tpl, near, ev, z, cur, res);
    }
    res.z = z;
    res.score = cur.log_l;
    // Sliding along a corridor or a single wall can carry the optimum far from the
    // prediction: such a result is not an observation of this landmark.
    const Vec3 corr = poseDifference(z, z0);
    if (corr.head<2>().norm() > options_.max_correction_m ||
        std::abs(corr.z()) > options_.max_correction)
    {
        res.failure = "diverged";
        return res;
    }
    if (static_cast<double>(cur.matched) <
        options_.min_matched_fraction * static_cast<double>(tpl.size()))
    {
        res.failure = "too_few_matches";
        return res;
    }
    const std::optional<Mat3> cov = sampledCovariance(*this, tpl, near, z, cur);
    if (!cov)
    {
        res.failure = "covariance_not_positive";
        return res;
    }
    res.z = z;
    return finishAlignment(res, *cov, options_.cov_inflation);
}

}  // namespace hymm::scanslam
