/**
 * @file ScanOdometry.cpp
 * @brief Consecutive-scan alignment fused with the wheel odometry (ScanOdometry.h).
 */
#include "hymm/scanslam/ScanOdometry.h"

#include <hymm/ekf/pose_composition.h>
#include <mrpt/math/distributions.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

namespace hymm::scanslam
{
ScanOdometry::ScanOdometry(const Options& options, std::unique_ptr<ScanMatcher> matcher)
    : options_(options),
      matcher_(std::move(matcher)),
      turn_bias_var_(options.wheel_turn_bias_prior * options.wheel_turn_bias_prior)
{
    if (!matcher_) throw std::invalid_argument("ScanOdometry: no matcher");
}

PointSet ScanOdometry::usablePoints(const mrpt::obs::CObservation2DRangeScan& scan) const
{
    const PointSet all = fromScan(scan, options_.noise);
    PointSet out;
    for (size_t i = 0; i < all.size(); ++i)
        if (all.range.empty() || all.range[i] <= options_.max_range_m) out.add(all.points[i], all.covs[i]);
    return out;
}

namespace
{
/** Every k-th point, k the smallest stride that keeps at most `n`. */
PointSet thinned(const PointSet& set, size_t n)
{
    if (set.size() <= n) return set;
    const size_t k = (set.size() + n - 1) / n;
    PointSet out;
    for (size_t i = 0; i < set.size(); i += k) out.add(set.points[i], set.covs[i]);
    return out;
}

Mat3 symmetric(const Mat3& m) { return 0.5 * (m + m.transpose()); }

/** The points of `set` (previous sensor frame) that, placed by z (previous sensor frame
 *  in the current one), lie inside `scan`'s field of view and within `max_range` (and
 *  the scan's) with a margin (the prediction is uncertain by about the margin). */
PointSet inViewOf(const PointSet& set, const Vec3& z, const mrpt::obs::CObservation2DRangeScan& scan,
                  double max_range)
{
    constexpr double kMarginAngle = 3 * M_PI / 180;  // [rad]
    constexpr double kMarginRange = 1.0;             // [m]
    const double half = 0.5 * scan.aperture - kMarginAngle;
    const double reach = std::min<double>(scan.maxRange, max_range) - kMarginRange;
    PointSet out;
    for (size_t i = 0; i < set.size(); ++i)
    {
        const Vec2 q = transformPoint(z, set.points[i]);
        if (std::abs(std::atan2(q.y(), q.x())) <= half && q.norm() <= reach) out.add(set.points[i], set.covs[i]);
    }
    return out;
}
}  // namespace

void ScanOdometry::reset()
{
    updateTurnBias();
    has_reference_ = false;
    since_reference_ = Increment{};
    last_relative_.reset();
    last_is_reference_ = false;
}

bool ScanOdometry::wheelTurnBiasApplied() const
{
    return options_.wheel_turn_bias &&
           std::abs(turn_bias_) > options_.wheel_turn_bias_min_sigmas * std::sqrt(turn_bias_var_);
}

ScanOdometry::Increment ScanOdometry::unbiasedWheel(const Increment& wheel)
{
    if (!wheelTurnBiasApplied() || !wheel.mean.allFinite()) return wheel;
    ++stats_.bias_applied;
    // The wheels turn b ds too little over a step of length ds; the extra turn accrues
    // along the step, so the translation turns by half of it (the mid-point heading).
    // The mean is core::turnBiasedIncrement's up to rounding; it is kept written out
    // because the covariance here rotates by the turn only (no d turn / d ds term) and
    // the shipped Intel figures were measured with exactly this (docs/results.md).
    const double ds = wheel.mean.head<2>().norm();
    const double turn = turn_bias_ * ds;
    Mat3 J = Mat3::Identity();
    J.topLeftCorner<2, 2>() = rotation(0.5 * turn);
    Increment out;
    out.mean.head<2>() = J.topLeftCorner<2, 2>() * wheel.mean.head<2>();
    out.mean.z() = std::remainder(wheel.mean.z() + turn, 2 * M_PI);
    out.cov = symmetric(J * wheel.cov * J.transpose());
    out.cov(2, 2) += turn_bias_var_ * ds * ds;  // the bias' own uncertainty over this step
    return out;
}

void ScanOdometry::observeTurn(const Increment& wheel_read, const std::optional<Increment>& relative)
{
    // The wheels as read since the reference: the alignment's heading relative to it
    // minus theirs measures their turn bias over the distance they travelled.
    wheel_since_reference_ = composeIncrements(wheel_since_reference_, wheel_read);
    wheel_distance_since_reference_ += wheel_read.mean.head<2>().norm();
    if (relative)
        turn_observation_ = TurnObservation{
            std::remainder(relative->mean.z() - wheel_since_reference_.mean.z(), 2 * M_PI),
            wheel_distance_since_reference_, relative->cov(2, 2) + wheel_since_reference_.cov(2, 2)};
}

void ScanOdometry::updateTurnBias()
{
    const auto observation = turn_observation_;
    const double travelled = wheel_distance_since_reference_;
    turn_observation_.reset();
    wheel_since_reference_ = Increment{};
    wheel_distance_since_reference_ = 0;
    if (!options_.wheel_turn_bias || !observation) return;
    const TurnObservation& o = *observation;
    if (!(o.ds > 0) || !std::isfinite(o.e) || !(o.var > 0)) return;
    // A scalar Kalman filter of b: a random walk over the distance travelled, observed
    // by e = b ds + n, var(n) = the alignment's heading variance plus the wheels'.
    if (std::isfinite(travelled)) turn_bias_var_ += options_.wheel_turn_bias_walk * options_.wheel_turn_bias_walk * travelled;
    const double S = o.ds * o.ds * turn_bias_var_ + o.var;
    const double nu = o.e - turn_bias_ * o.ds;
    if (options_.gate_prob > 0 && options_.gate_prob < 1 && nu * nu / S > mrpt::math::chi2inv(options_.gate_prob, 1))
    {
        ++stats_.bias_gated;
        return;
    }
    const double K = turn_bias_var_ * o.ds / S;
    turn_bias_ += K * nu;
    turn_bias_var_ *= o.var / S;  // (1 - K ds), in the form that stays positive
    ++stats_.bias_updates;
}

ScanOdometry::Increment ScanOdometry::refine(const mrpt::obs::CObservation2DRangeScan& scan, const Increment& wheel_read)
{
    ++stats_.scans;
    const Increment wheel = unbiasedWheel(wheel_read);
    const Vec3 mount(scan.sensorPose.x(), scan.sensorPose.y(), scan.sensorPose.yaw());
    const PointSet current = usablePoints(scan);
    std::optional<Increment> relative;  // the fused alignment: the pose relative to the reference
    Increment out = wheel;
    if (!has_reference_)
        ++stats_.no_reference;
    else
    {
        out = aligned(scan, current, mount, wheel, relative);
        // Only a fused step is scaled; the wheels alone keep their covariance (README,
        // "Covariance of the steps").
        if (relative) out.cov *= options_.step_cov_scale;
        if (options_.wheel_turn_bias) observeTurn(wheel_read, relative);
    }
    const bool ok = relative.has_value();
    last_relative_ = relative;
    const Vec3& v = since_reference_.mean;
    // A new keyframe: always without keyframes; after a failed alignment (the chain to the
    // old one is broken); or once the vehicle has left the keyframe's neighbourhood.
    const bool renew = !ok || options_.keyframe_distance_m <= 0 ||
                       v.head<2>().norm() > options_.keyframe_distance_m ||
                       std::abs(v.z()) > options_.keyframe_angle || !v.allFinite();
    if (renew)
    {
        updateTurnBias();
        reference_ = thinned(current, options_.max_points);
        reference_mount_ = mount;
        since_reference_ = Increment{};
        handed_cov_ = Mat3::Zero();
        has_reference_ = true;
        reference_is_previous_ = true;
        ++stats_.keyframes;
    }
    else
        reference_is_previous_ = false;
    last_is_reference_ = renew;
    return out;
}

ScanOdometry::Increment ScanOdometry::aligned(const mrpt::obs::CObservation2DRangeScan& scan, const PointSet& current,
                                              const Vec3& mount, const Increment& wheel,
                                              std::optional<Increment>& relative_measured)
{
    // The matcher places a "template" (the reference scan, in its sensor frame) in the
    // current sensor frame: z = s^-1 for the sensor's pose s = m_ref^-1 (+) v (+) m, v the
    // vehicle relative to its pose at the reference; b is v at the previous scan. When the
    // reference is the previous scan (always without keyframes) v is the increment itself,
    // and the expressions below are those of scan-to-scan odometry, operation for operation.
    const bool previous = reference_is_previous_;
    const Increment before = since_reference_;
    const auto relative = [&](const Vec3& z) { return compose(compose(reference_mount_, inverse(z)), inverse(mount)); };
    const auto increment = [&](const Vec3& z) {
        return previous ? relative(z) : compose(inverse(before.mean), relative(z));
    };
    const Increment predicted = previous ? wheel : composeIncrements(before, wheel);
    const Vec3 z0 = inverse(compose(compose(inverse(reference_mount_), predicted.mean), mount));
    // Only the reference returns the current scan can see again: the others have no
    // counterpart and bias the increment (README, "Why only the returns seen again").
    const bool usable = current.size() >= 3 && reference_.size() >= 3 && wheel.mean.allFinite();
    const PointSet overlap = usable ? inViewOf(reference_, z0, scan, options_.max_range_m) : PointSet{};
    if (overlap.size() < 3)
    {
        ++stats_.too_few_points;
        return wheel;
    }
    const AlignResult r = matcher_->align(overlap, current, z0);
    if (!r.ok)
    {
        ++stats_.align_failed[r.failure];
        return wheel;
    }
    // The wheels fused with the alignment as a measurement of this step: gate and covariance.
    double d2 = 0;
    const Increment measured = alignedIncrement(r, increment);
    const Increment step = fuseIncrements(wheel, measured, &d2);
    const bool gate = options_.gate_prob > 0 && options_.gate_prob < 1;
    if (!std::isfinite(d2) || (gate && d2 > mrpt::math::chi2inv(options_.gate_prob, 3)))
    {
        ++stats_.gated;
        return wheel;
    }
    ++stats_.fused;
    if (previous)
    {
        since_reference_ = step;
        handed_cov_ = step.cov;
        relative_measured = measured;
        return step;
    }
    // The pose relative to the reference: predicted by the wheels from its last estimate,
    // updated by the alignment (a direct measurement of it). Its step is the increment.
    relative_measured = alignedIncrement(r, relative);
    since_reference_ = fuseIncrements(predicted, *relative_measured);
    const Vec3 mean = compose(inverse(before.mean), since_reference_.mean);
    if (options_.keyframe_step_cov == Options::KeyframeStepCov::alignment) return {mean, step.cov};
    return {mean, covarianceGrowth(before, since_reference_.cov, mean, step.cov)};
}

Mat3 ScanOdometry::covarianceGrowth(const Increment& before, const Mat3& after, const Vec3& step, const Mat3& fallback)
{
    // The filter composes the steps: H' = Ja H Ja^T + Jb Q Jb^T (composeIncrements, a =
    // the relative pose before the step, b = the step), H the covariance of the steps
    // handed on since the reference. Q is solved for H' = after, the relative pose's.
    Mat3 Ja, Jb;
    (void)ekf::composePose(before.mean, step, &Ja, &Jb);
    const Mat3 carried = Ja * handed_cov_ * Ja.transpose();
    const Mat3 Q = symmetric(Jb.transpose() * (after - carried) * Jb);  // Jb is a rotation: Jb^-1 = Jb^T
    Eigen::SelfAdjointEigenSolver<Mat3> es;
    if (Q.allFinite()) es.compute(Q);
    if (!Q.allFinite() || es.info() != Eigen::Success)
    {
        handed_cov_ = symmetric(carried + Jb * fallback * Jb.transpose());
        return fallback;
    }
    // An update can shrink the relative pose's covariance below what the filter already
    // holds for the earlier steps (they share the reference's error): the step's negative
    // share is clamped to zero, and the excess is kept in H, so later steps pay it back
    // rather than adding up clamps.
    const Vec3 d = es.eigenvalues();
    if ((d.array() < 0).any()) ++stats_.growth_clamped;
    const Mat3 out = symmetric(es.eigenvectors() * d.cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose());
    handed_cov_ = symmetric(carried + Jb * out * Jb.transpose());
    return out;
}

ScanOdometry::Increment ScanOdometry::alignedIncrement(const AlignResult& r,
                                                       const std::function<Vec3(const Vec3&)>& increment) const
{
    // du/dz by central differences (the map is smooth; 3 columns).
    Mat3 J;
    constexpr double h = 1e-6;
    for (int k = 0; k < 3; ++k)
    {
        Vec3 dz = Vec3::Zero();
        dz(k) = h;
        J.col(k) = poseDifference(increment(r.z + dz), increment(r.z - dz)) / (2 * h);
    }
    Increment s;
    s.mean = increment(r.z);
    s.cov = symmetric(J * r.R * J.transpose()) * options_.cov_scale;
    const double k = std::sqrt(options_.heading_cov_scale);  // its variance times the factor
    s.cov.row(2) *= k;
    s.cov.col(2) *= k;
    const double travel = s.mean.head<2>().norm();
    const double sxy = options_.min_std_xy_m + options_.std_xy_per_m * travel;
    const double sphi = options_.min_std_phi + options_.std_phi_per_m * travel;
    s.cov(0, 0) += sxy * sxy;
    s.cov(1, 1) += sxy * sxy;
    s.cov(2, 2) += sphi * sphi;
    return s;
}

ScanOdometry::Increment composeIncrements(const ScanOdometry::Increment& a, const ScanOdometry::Increment& b)
{
    Mat3 Ja, Jb;
    (void)ekf::composePose(a.mean, b.mean, &Ja, &Jb);
    ScanOdometry::Increment out;
    out.mean = compose(a.mean, b.mean);
    out.cov = symmetric(Ja * a.cov * Ja.transpose() + Jb * b.cov * Jb.transpose());
    return out;
}

ScanOdometry::Increment fuseIncrements(const ScanOdometry::Increment& w, const ScanOdometry::Increment& s,
                                       double* d2)
{
    const Vec3 e = poseDifference(s.mean, w.mean);
    const Mat3 S = symmetric(w.cov + s.cov);
    const Eigen::LDLT<Mat3> ldlt(S);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || (ldlt.vectorD().array() <= 0).any() || !e.allFinite())
    {
        if (d2) *d2 = std::numeric_limits<double>::infinity();
        return w;
    }
    if (d2) *d2 = e.dot(ldlt.solve(e));
    // K = P_w S^-1; Joseph form keeps the result symmetric PSD.
    const Mat3 K = ldlt.solve(w.cov.transpose()).transpose();
    const Mat3 IK = Mat3::Identity() - K;
    ScanOdometry::Increment out;
    out.mean = w.mean + K * e;
    out.mean.z() = std::remainder(out.mean.z(), 2 * M_PI);
    out.cov = symmetric(IK * w.cov * IK.transpose() + K * s.cov * K.transpose());
    return out;
}

}  // namespace hymm::scanslam
