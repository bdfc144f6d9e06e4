#include "hymm/extract/scan_features.h"

#include <mrpt/poses/CPose3D.h>

namespace hymm::extract
{
mrpt::obs::CObservationBearingRange toBearingRangeObservation(
    const mrpt::obs::CObservation2DRangeScan& scan, const std::vector<ScanFeature>& features,
    const BearingRangeNoise& noise)
{
    mrpt::obs::CObservationBearingRange obs;
    obs.timestamp = scan.timestamp;
    obs.sensorLabel = scan.sensorLabel;
    obs.sensorLocationOnRobot = scan.sensorPose;
    obs.minSensorDistance = 0;
    obs.maxSensorDistance = scan.maxRange;
    obs.fieldOfView_yaw = scan.aperture;
    obs.fieldOfView_pitch = 0;
    obs.validCovariances = false;
    obs.sensor_std_range = static_cast<float>(noise.std_range);
    obs.sensor_std_yaw = static_cast<float>(noise.std_bearing);
    obs.sensor_std_pitch = 0;

    mrpt::math::CMatrixDouble33 cov;
    cov.setZero();
    cov(0, 0) = noise.std_range * noise.std_range;
    cov(1, 1) = noise.std_bearing * noise.std_bearing;

    obs.sensedData.reserve(features.size());
    for (const auto& f : features)
    {
        mrpt::obs::CObservationBearingRange::TMeasurement m;
        m.range = static_cast<float>(f.range);
        m.yaw = static_cast<float>(f.bearing);
        m.pitch = 0;
        m.landmarkID = -1;  // unidentified: data association is the EKF's job
        m.covariance = cov;
        obs.sensedData.push_back(m);
    }
    return obs;
}

}  // namespace hymm::extract
