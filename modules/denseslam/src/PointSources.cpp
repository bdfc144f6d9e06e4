// The registered point sources (LandmarkSources.h): a range-bearing sensor's
// observations, beacons and trunks extracted from laser scans.
#include "PointSources.h"

#include "usable_covariance.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <cmath>

namespace hymm::denseslam
{
Eigen::Matrix2d PointSourceSettings::noise(double std_range, double std_bearing) const
{
    const double sr = sensor_std_range > 0 ? sensor_std_range : std_range;
    const double sb = sensor_std_bearing > 0 ? sensor_std_bearing : std_bearing;
    return Eigen::Vector2d(sr * sr, sb * sb).asDiagonal();
}

PointObservations BearingRangeSource::observe(const mrpt::obs::CObservation& o) const
{
    const auto& obs = dynamic_cast<const mrpt::obs::CObservationBearingRange&>(o);
    PointObservations out;
    out.z.reserve(obs.sensedData.size());
    const Eigen::Matrix2d R_default = settings_.noise(obs.sensor_std_range, obs.sensor_std_yaw);
    for (const auto& m : obs.sensedData)
    {
        if (!std::isfinite(m.range) || !std::isfinite(m.yaw) || m.range < settings_.min_range ||
            m.range > settings_.max_range || m.range <= 0)
        {
            ++out.skipped_invalid;
            continue;
        }
        ekf::RangeBearingObs z;
        z.z = Eigen::Vector2d(m.range, mrpt::math::wrapToPi(m.yaw));
        z.R = R_default;
        if (obs.validCovariances && settings_.sensor_std_range <= 0)
        {
            // Per-measurement covariance of (range, yaw) from the 3x3 (range, yaw, pitch); one
            // that is no covariance, or spreads wider than the sensor's range or a half
            // turn, is a corrupt reading.
            z.R << m.covariance(0, 0), m.covariance(0, 1), m.covariance(1, 0), m.covariance(1, 1);
            if (!usableCovariance<2>(z.R, Eigen::Vector2d(settings_.max_range, M_PI)))
            {
                ++out.skipped_invalid;
                continue;
            }
        }
        z.id = settings_.use_landmark_ids ? m.landmarkID : -1;
        out.z.push_back(z);
    }
    return out;
}

namespace
{
/** Every feature of a scan as an observation with its extractor's noise. */
PointObservations fromFeatures(const std::vector<extract::ScanFeature>& features, size_t skipped,
                               const Eigen::Matrix2d& R)
{
    PointObservations out;
    out.skipped_invalid = skipped;
    for (const auto& f : features)
    {
        ekf::RangeBearingObs z;
        z.z = Eigen::Vector2d(f.range, f.bearing);
        z.R = R;
        out.z.push_back(z);
        out.beams.emplace_back(f.first_beam, f.last_beam);
    }
    return out;
}
}  // namespace

template <>
PointObservations ReflectorSource::observe(const mrpt::obs::CObservation& o) const
{
    const auto& scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan&>(o);
    // Scans without intensities carry no beacons (the extractor would throw).
    if (!scan.hasIntensity()) return {};
    const auto res = extractor_.extract(scan);
    return fromFeatures(res.reflectors, res.skipped_invalid,
                        settings_.noise(extractor_.options().std_range, extractor_.options().std_bearing));
}

template <>
PointObservations TreeSource::observe(const mrpt::obs::CObservation& o) const
{
    const auto res = extractor_.extract(dynamic_cast<const mrpt::obs::CObservation2DRangeScan&>(o));
    return fromFeatures(res.trees, res.skipped_invalid,
                        settings_.noise(extractor_.options().std_range, extractor_.options().std_bearing));
}

}  // namespace hymm::denseslam
