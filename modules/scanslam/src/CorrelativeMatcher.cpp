/**
 * @file CorrelativeMatcher.cpp
 * @brief Exhaustive two-level correlative search with the score-surface covariance.
 */
#include "hymm/scanslam/CorrelativeMatcher.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "hymm/core/config_utils.h"
#include "LikelihoodGrid.h"

namespace hymm::scanslam
{
CorrelativeMatcher::CorrelativeMatcher() : options_() {}

hymm::core::OptionTable CorrelativeMatcher::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("sigma_m", sigma_m, "m", above(0, 100), "point likelihood std");
    t.real("gate_sigma", gate_sigma, "sigma", above(0, 1000), "log-likelihood floor at this distance");
    // A lower bound on cells and steps: a typo (1e-6) would ask for a grid of terabytes.
    t.real("grid_resolution_m", grid_resolution_m, "m", atLeast(0.001, 10), "likelihood grid cell");
    t.real("search_xy_m", search_xy_m, "m", atLeast(0, 100), "half search window in x and y");
    t.real("search_phi_deg", search_phi, "deg", atLeast(0, 180), "half search window in angle",
           M_PI / 180);
    t.real("coarse_step_m", coarse_step_m, "m", atLeast(0.001, 10), "coarse translation step (angle step: this / template radius)");
    t.real("fine_step_m", fine_step_m, "m", atLeast(0.001, 10), "fine translation step, searched +-one coarse step around the coarse best");
    t.real("min_matched_fraction", min_matched_fraction, "", between(0, 1),
           "template points above the floor at the best pose");
    t.real("cov_inflation", cov_inflation, "", above(0, 1000), "covariance multiplier (measured, see above)");
    return t;
}

void CorrelativeMatcher::Options::load(const mrpt::config::CConfigFileBase& cfg,
                                       const std::string& section)
{
    table().load(cfg, section);
}

namespace
{
std::vector<Vec2> rotate(const std::vector<Vec2>& pts, double phi)
{
    const Mat2 r = rotation(phi);
    std::vector<Vec2> out;
    out.reserve(pts.size());
    for (const Vec2& p : pts) out.push_back(r * p);
    return out;
}

using Options = CorrelativeMatcher::Options;

/** Coarse search: translation steps of coarse_step, angle steps of `cphi` (moving the
 *  template's furthest point by about the same distance); the best pose. */
Vec3 coarseSearch(const LikelihoodGrid& coarse, const PointSet& tpl, const Vec3& z0, const Options& o,
                  double cphi, AlignResult& res)
{
    const int nxy = static_cast<int>(std::ceil(o.search_xy_m / o.coarse_step_m));
    const int nphi = static_cast<int>(std::ceil(o.search_phi / cphi));
    double best = -std::numeric_limits<double>::infinity();
    Vec3 zc = z0;
    std::vector<double> scores;
    for (int k = -nphi; k <= nphi; ++k)
    {
        const double phi = z0.z() + k * cphi;
        coarse.scoreLattice(rotate(tpl.points, phi), z0.x(), z0.y(), o.coarse_step_m, nxy, nxy, scores);
        const double* s = scores.data();
        for (int iy = -nxy; iy <= nxy; ++iy)
            for (int ix = -nxy; ix <= nxy; ++ix, ++s)
            {
                ++res.iterations;
                if (*s > best)
                {
                    best = *s;
                    zc = Vec3(z0.x() + ix * o.coarse_step_m, z0.y() + iy * o.coarse_step_m, phi);
                }
            }
    }
    return zc;
}

/** The scores of the fine search around the coarse cell at zc (offsets from zc, angle
 *  steps fphi); `fbest` and `zbest`: the best of them. */
std::vector<std::pair<Vec3, double>> fineSamples(const LikelihoodGrid& fine, const PointSet& tpl, const Vec3& zc,
                                                 const Options& o, double cphi, double fphi, double& fbest,
                                                 Vec3& zbest, AlignResult& res)
{
    const int fxy = static_cast<int>(std::ceil(o.coarse_step_m / o.fine_step_m));
    const int fph = static_cast<int>(std::ceil(cphi / fphi));
    std::vector<std::pair<Vec3, double>> samples;
    samples.reserve(static_cast<size_t>((2 * fxy + 1) * (2 * fxy + 1) * (2 * fph + 1)));
    fbest = -std::numeric_limits<double>::infinity();
    zbest = zc;
    std::vector<double> scores;
    for (int k = -fph; k <= fph; ++k)
    {
        const double dphi = k * fphi;
        fine.scoreLattice(rotate(tpl.points, zc.z() + dphi), zc.x(), zc.y(), o.fine_step_m, fxy, fxy, scores);
        const double* sc = scores.data();
        for (int iy = -fxy; iy <= fxy; ++iy)
            for (int ix = -fxy; ix <= fxy; ++ix, ++sc)
            {
                const Vec3 d(ix * o.fine_step_m, iy * o.fine_step_m, dphi);
                const double s = *sc;
                ++res.iterations;
                samples.emplace_back(d, s);
                if (s > fbest)
                {
                    fbest = s;
                    zbest = zc + d;
                }
            }
    }
    return samples;
}

/** Mean offset and covariance of the score surface (weights exp(s - fbest)), with the
 *  variance of the uniform quantisation to the fine steps added. */
Vec3 surfaceMoments(const std::vector<std::pair<Vec3, double>>& samples, double fbest, double step_m,
                    double fphi, Mat3& cov)
{
    double wsum = 0;
    Vec3 mean = Vec3::Zero();
    Mat3 second = Mat3::Zero();
    for (const auto& [d, s] : samples)
    {
        const double w = std::exp(s - fbest);
        wsum += w;
        mean += w * d;
        second += w * d * d.transpose();
    }
    mean /= wsum;
    cov = second / wsum - mean * mean.transpose();
    cov(0, 0) += step_m * step_m / 12;
    cov(1, 1) += step_m * step_m / 12;
    cov(2, 2) += fphi * fphi / 12;
    return mean;
}
}  // namespace

AlignResult CorrelativeMatcher::align(const PointSet& tpl, const PointSet& scan, const Vec3& z0) const
{
    if (auto bad = rejectInput(tpl, scan, z0)) return *bad;
    AlignResult res;
    res.z = z0;
    const auto& o = options_;
    double radius = 0;
    for (const Vec2& p : tpl.points) radius = std::max(radius, p.norm());
    radius = std::max(radius, 0.5);
    const double coarse_sigma = std::max(o.sigma_m, o.coarse_step_m);
    const double margin = o.search_xy_m + radius + o.gate_sigma * coarse_sigma + 2 * o.grid_resolution_m;
    const Vec2 lo = z0.head<2>() - Vec2::Constant(margin);
    const Vec2 hi = z0.head<2>() + Vec2::Constant(margin);
    const LikelihoodGrid coarse(lo, hi, o.grid_resolution_m, coarse_sigma, o.gate_sigma, scan);
    const LikelihoodGrid fine(lo, hi, o.grid_resolution_m, o.sigma_m, o.gate_sigma, scan);

    const double cphi = o.coarse_step_m / radius;
    const Vec3 zc = coarseSearch(coarse, tpl, z0, o, cphi, res);
    // Fine search around the coarse cell; the score surface gives mean and covariance.
    const double fphi = o.fine_step_m / radius;
    double fbest = 0;
    Vec3 zbest;
    const auto samples = fineSamples(fine, tpl, zc, o, cphi, fphi, fbest, zbest, res);
    Mat3 cov;
    const Vec3 mean = surfaceMoments(samples, fbest, o.fine_step_m, fphi, cov);
    res.z = zc + mean;
    res.z.z() = mrpt::math::wrapToPi(res.z.z());
    res.score = fbest;

    // Matched points at the best pose: above the floor of the fine grid.
    size_t matched = 0;
    for (const Vec2& p : tpl.points)
    {
        const Vec2 q = transformPoint(zbest, p);
        if (fine.at(q.x(), q.y()) > fine.floorValue() + 1e-9) ++matched;
    }
    if (static_cast<double>(matched) < o.min_matched_fraction * static_cast<double>(tpl.size()))
    {
        res.failure = "too_few_matches";
        return res;
    }
    return finishAlignment(res, cov, o.cov_inflation);
}

}  // namespace hymm::scanslam
