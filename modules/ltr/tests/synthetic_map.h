/**
 * @file synthetic_map.h
 * @brief Test helper: a feature map with a SLAM-like joint covariance.
 *
 * Every state shares a common position error g ~ N(0, sigma_common^2 I) (the vehicle
 * uncertainty propagated into everything it observed, Sec. 3.3); the vehicle adds
 * independent noise (sigma_vehicle) and a heading error (sigma_heading); landmark i adds
 * independent noise sigma_0 + growth * distance(landmark i, vehicle). So landmarks
 * near the vehicle are highly correlated with it and with each other.
 */
#pragma once

#include "hymm/ltr/DenseCovarianceView.h"

#include <map>
#include <vector>

namespace hymm::ltr::synthetic
{
struct SyntheticNoise
{
    double sigma_common = 1.0;
    double sigma_vehicle = 0.05;
    double sigma_heading = 0.02;
    double sigma_0 = 0.05;
    double growth = 0.02;  // extra sigma per metre from the vehicle
};

/** Landmark ids are 100 + index. */
inline DenseCovarianceView makeSyntheticView(
    const std::vector<Eigen::Vector2d>& landmarks, const Eigen::Vector3d& vehicle,
    const SyntheticNoise& noise = SyntheticNoise())
{
    const int n = 3 + 2 * static_cast<int>(landmarks.size());
    Eigen::VectorXd mean(n);
    Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, 2);  // loading of the common error
    Eigen::VectorXd indep(n);
    mean.head<3>() = vehicle;
    g.block<2, 2>(0, 0).setIdentity();
    indep(0) = indep(1) = noise.sigma_vehicle * noise.sigma_vehicle;
    indep(2) = noise.sigma_heading * noise.sigma_heading;
    std::map<long, int> offsets;
    for (size_t i = 0; i < landmarks.size(); ++i)
    {
        const int o = 3 + 2 * static_cast<int>(i);
        offsets[100 + static_cast<long>(i)] = o;
        mean.segment<2>(o) = landmarks[i];
        g.block<2, 2>(o, 0).setIdentity();
        const double s =
            noise.sigma_0 + noise.growth * (landmarks[i] - vehicle.head<2>()).norm();
        indep(o) = indep(o + 1) = s * s;
    }
    Eigen::MatrixXd cov = noise.sigma_common * noise.sigma_common * g * g.transpose();
    cov.diagonal() += indep;
    return DenseCovarianceView(mean, cov, offsets, 0);
}

}  // namespace hymm::ltr::synthetic
