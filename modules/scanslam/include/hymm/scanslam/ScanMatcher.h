/**
 * @file ScanMatcher.h
 * @brief One interface for scan alignment (thesis 5.2.1, 5.4):
 *        [z, R] = scan_align(template, scan, z_hat), where z is the pose of the
 *        template's frame in the scan's (sensor) frame and R its covariance.
 *
 * Implementations: SogMatcher (the thesis' sum-of-Gaussians correlation with the
 * covariance of 5.4), IcpMatcher (mrpt::slam::CICP and its covariance) and
 * CorrelativeMatcher (exhaustive search over a likelihood grid, covariance from the
 * score surface). Each multiplies its covariance by `cov_inflation`, a factor measured
 * by the NEES study of the README (1 = the matcher's own covariance).
 */
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <memory>
#include <string>

#include <optional>

#include "hymm/scanslam/PointSet.h"
#include "hymm/scanslam/ScanTemplate.h"

namespace hymm::scanslam
{
struct AlignResult
{
    bool ok = false;
    Vec3 z = Vec3::Zero();  //!< template frame in the scan frame
    Mat3 R = Mat3::Identity();
    int iterations = 0;
    double score = 0;    //!< matcher-specific quality (higher is better)
    const char* failure = "";  //!< why ok is false
};

class ScanMatcher
{
public:
    virtual ~ScanMatcher() = default;

    /** Aligns `tpl` (landmark frame) to `scan` (sensor frame) from the initial guess
     *  `z0`. Never throws on bad data: empty sets, a non-converging search or a
     *  covariance that is not positive definite give ok = false with a reason. */
    virtual AlignResult align(const PointSet& tpl, const PointSet& scan, const Vec3& z0) const = 0;

    virtual std::string name() const = 0;
};

/** "sog", "icp" or "correlative", options read from [section] when `cfg` is given. */
std::unique_ptr<ScanMatcher> makeMatcher(const std::string& kind,
                                         const mrpt::config::CConfigFileBase* cfg = nullptr,
                                         const std::string& section = "");

/** Symmetric positive definite check with a floor on the smallest eigenvalue. */
bool isCovariance(const Mat3& c, double min_eig = 1e-12);

/** The checks every matcher makes first: at least three template and scan points and a
 *  finite guess. Returns a result at z0 with `failure` set, or nothing when usable. */
std::optional<AlignResult> rejectInput(const PointSet& tpl, const PointSet& scan, const Vec3& z0);

/** Ends an alignment at res.z: `cov` symmetrised and scaled by the matcher's measured
 *  `inflation` (docs/benchmarks.md) becomes res.R with ok = true, unless it is not a
 *  covariance or res.z is not finite (failure "covariance_not_positive"). */
AlignResult& finishAlignment(AlignResult& res, const Mat3& cov, double inflation);

}  // namespace hymm::scanslam
