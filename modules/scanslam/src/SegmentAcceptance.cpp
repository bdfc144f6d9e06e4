/**
 * @file SegmentAcceptance.cpp
 * @brief Registration self-test of candidate segments (thesis 5.2.2, 5.7).
 */
#include "hymm/scanslam/SegmentAcceptance.h"

#include <Eigen/Cholesky>
#include <cmath>

#include "hymm/core/config_utils.h"

namespace hymm::scanslam
{
core::OptionTable SegmentAcceptance::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.integer("trials", trials, "", 1, 1000, "perturbed copies per segment; all must pass");
    t.real("displacement_xy_m", displacement_xy_m, "m", atLeast(0, 100),
           "length of the random translation (random direction)");
    t.real("displacement_phi_deg", displacement_phi, "deg", atLeast(0, 180), "size of the random rotation (random sign)",
           M_PI / 180);
    t.real("max_error_fraction", max_error_fraction, "", above(0, 100),
           "RMS point error / RMS point displacement (thesis 10 %)");
    t.real("max_cov_trace", max_cov_trace, "m^2", atLeast(0, 1e6),
           "also require trace of the xy covariance below this (0: off)");
    t.real("min_extent_m", min_extent_m, "m", atLeast(0, 1000), "segments shorter end to end are `too_small`");
    return t;
}

void SegmentAcceptance::Options::load(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    table().load(cfg, section);
    if (displacement_xy_m <= 0 && displacement_phi <= 0)
        core::throwConfigError(section, "displacement_xy_m", "0", "some displacement is needed");
}

void SegmentAcceptance::Options::save(mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    auto copy = *this;
    copy.table().save(cfg, section);
}

const char* SegmentAcceptance::outcomeName(Outcome o)
{
    switch (o)
    {
        case Outcome::accepted: return "accepted";
        case Outcome::too_small: return "too_small";
        case Outcome::registration_failed: return "registration_failed";
        case Outcome::error_too_large: return "error_too_large";
        case Outcome::covariance_too_large: return "covariance_too_large";
    }
    return "?";
}

size_t SegmentAcceptance::Stats::total() const
{
    size_t n = 0;
    for (size_t c : count) n += c;
    return n;
}

SegmentAcceptance::SegmentAcceptance(const Options& options, const ScanMatcher& matcher,
                                     uint32_t seed)
    : options_(options), matcher_(matcher)
{
    rng_.randomize(seed);
}

namespace
{
double rmsDisplacement(const PointSet& pts, const Vec3& a, const Vec3& b)
{
    double s = 0;
    for (const Vec2& p : pts.points) s += (transformPoint(a, p) - transformPoint(b, p)).squaredNorm();
    return std::sqrt(s / static_cast<double>(pts.size()));
}
}  // namespace

SegmentAcceptance::Outcome SegmentAcceptance::test(const PointSet& segment, double* worst_ratio)
{
    const auto count = [&](Outcome o) {
        ++stats_.count[static_cast<size_t>(o)];
        return o;
    };
    if (worst_ratio) *worst_ratio = std::numeric_limits<double>::infinity();
    if (segment.size() < 3) return count(Outcome::too_small);
    if ((segment.points.front() - segment.points.back()).norm() < options_.min_extent_m)
        return count(Outcome::too_small);
    const ScanTemplate tpl = ScanTemplate::fromPoints(segment);
    double worst = 0;
    for (int t = 0; t < options_.trials; ++t)
    {
        // A re-observation of the segment: fresh noise of each point's own covariance,
        // then the whole copy displaced by a random rigid motion.
        // Fixed magnitudes in random directions: a Gaussian draw can come out near zero
        // and make the error/displacement ratio meaningless.
        const double dir = rng_.drawUniform(-M_PI, M_PI);
        const double sgn = rng_.drawUniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0;
        const Vec3 disp(options_.displacement_xy_m * std::cos(dir),
                        options_.displacement_xy_m * std::sin(dir), sgn * options_.displacement_phi);
        PointSet copy;
        for (size_t i = 0; i < segment.size(); ++i)
        {
            const Eigen::LLT<Mat2> llt(segment.covs[i]);
            // One draw per statement: the order of two draws in one argument list is the
            // compiler's choice (GCC took the second first; clang the first), and results
            // must not depend on the compiler. This is GCC's order.
            const double ny = rng_.drawGaussian1D_normalized();
            const double nx = rng_.drawGaussian1D_normalized();
            const Vec2 n(nx, ny);
            const Vec2 noisy = segment.points[i] + (llt.info() == Eigen::Success
                                                       ? Vec2(llt.matrixL() * n)
                                                       : Vec2::Zero());
            copy.add(transformPoint(disp, noisy), segment.covs[i]);
        }
        const Vec3 truth = compose(disp, tpl.frame_in_sensor);
        const AlignResult r = matcher_.align(tpl.sog, copy, tpl.frame_in_sensor);
        if (!r.ok) return count(Outcome::registration_failed);
        const double moved = rmsDisplacement(tpl.sog, truth, tpl.frame_in_sensor);
        const double err = rmsDisplacement(tpl.sog, r.z, truth);
        const double ratio = moved > 0 ? err / moved : std::numeric_limits<double>::infinity();
        worst = std::max(worst, ratio);
        if (worst_ratio) *worst_ratio = worst;
        if (ratio > options_.max_error_fraction) return count(Outcome::error_too_large);
        if (options_.max_cov_trace > 0 && r.R(0, 0) + r.R(1, 1) > options_.max_cov_trace)
            return count(Outcome::covariance_too_large);
    }
    return count(Outcome::accepted);
}

}  // namespace hymm::scanslam
