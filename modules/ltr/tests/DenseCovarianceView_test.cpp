/**
 * @file DenseCovarianceView_test.cpp
 */
#include "hymm/ltr/DenseCovarianceView.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace
{
using hymm::ltr::DenseCovarianceView;

TEST(DenseCovarianceViewTest, ReadsBlocksAtTheirOffsets)
{
    const int n = 7;  // vehicle at 0, landmark 5 at 3, landmark 9 at 5
    Eigen::VectorXd mean = Eigen::VectorXd::LinSpaced(n, 0, n - 1);
    Eigen::MatrixXd cov(n, n);
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) cov(r, c) = 10 * r + c;
    const DenseCovarianceView v(mean, cov, {{5, 3}, {9, 5}}, 0);
    EXPECT_TRUE(v.has(5));
    EXPECT_FALSE(v.has(6));
    EXPECT_TRUE((v.mean(9) == Eigen::Vector2d(5, 6)));
    EXPECT_TRUE((v.cov(5) == cov.block<2, 2>(3, 3)));
    EXPECT_TRUE((v.crossCov(5, 9) == cov.block<2, 2>(3, 5)));
    EXPECT_TRUE((v.crossVehicle(9) == cov.block<2, 3>(5, 0)));
    EXPECT_TRUE((v.vehicleCov() == cov.block<3, 3>(0, 0)));
    EXPECT_TRUE((v.vehiclePose() == Eigen::Vector3d(0, 1, 2)));
    EXPECT_EQ(v.ids(), (std::vector<long>{5, 9}));
    EXPECT_THROW(v.mean(6), std::out_of_range);
}

TEST(DenseCovarianceViewTest, RejectsInconsistentLayouts)
{
    const Eigen::VectorXd mean = Eigen::VectorXd::Zero(5);
    EXPECT_THROW(DenseCovarianceView(mean, Eigen::MatrixXd::Zero(4, 4), {}), std::invalid_argument);
    EXPECT_THROW(
        DenseCovarianceView(mean, Eigen::MatrixXd::Zero(5, 5), {{1, 4}}), std::invalid_argument);
    EXPECT_THROW(
        DenseCovarianceView(mean, Eigen::MatrixXd::Zero(5, 5), {}, 3), std::invalid_argument);
}

}  // namespace
