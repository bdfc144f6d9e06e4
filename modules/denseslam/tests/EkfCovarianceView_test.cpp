// EkfCovarianceView against DenseCovarianceView over the same (mean, covariance): every
// accessor must read the same blocks; 3-DOF blocks and tentative landmarks are hidden.
#include <gtest/gtest.h>
#include <hymm/denseslam/EkfCovarianceView.h>
#include <hymm/ltr/DenseCovarianceView.h>

#include <algorithm>
#include <map>
#include <random>

namespace
{
using hymm::denseslam::EkfCovarianceView;

// Random SPD covariance of size n with non-trivial correlations.
Eigen::MatrixXd randomCov(int n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    Eigen::MatrixXd A(n, n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) A(i, j) = g(rng);
    Eigen::MatrixXd P = A * A.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
    // Exactly symmetric, so the filter stores it unchanged.
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < i; ++j) P(i, j) = P(j, i);
    return P;
}

TEST(EkfCovarianceView, ReadsTheSameBlocksAsADenseView)
{
    // Vehicle, point 7, pose-like block 3 (3 DOF), point 12.
    const int n = 3 + 2 + 3 + 2;
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) x[i] = 0.5 * i - 1.0;
    const Eigen::MatrixXd P = randomCov(n, 5);
    hymm::ekf::EkfSlam ekf{hymm::ekf::EkfSlam::Options()};
    ekf.setActiveState(x, P, {{7, 2}, {3, 3}, {12, 2}});
    ASSERT_TRUE(ekf.cov() == P);

    const EkfCovarianceView v(ekf);
    const hymm::ltr::DenseCovarianceView d(x, P, std::map<long, int>{{7, 3}, {12, 8}}, 0);

    EXPECT_EQ(v.ids(), (std::vector<long>{7, 12}));
    EXPECT_TRUE(v.has(7));
    EXPECT_TRUE(v.has(12));
    EXPECT_FALSE(v.has(3));   // 3-DOF block
    EXPECT_FALSE(v.has(99));  // unknown
    EXPECT_THROW(v.mean(3), std::out_of_range);
    EXPECT_THROW(v.cov(99), std::out_of_range);
    EXPECT_EQ(v.vehiclePose(), d.vehiclePose());
    EXPECT_EQ(v.vehicleCov(), d.vehicleCov());
    for (long a : {7L, 12L})
    {
        EXPECT_EQ(v.mean(a), d.mean(a));
        EXPECT_EQ(v.cov(a), d.cov(a));
        EXPECT_EQ(v.crossVehicle(a), d.crossVehicle(a));
        for (long b : {7L, 12L}) EXPECT_EQ(v.crossCov(a, b), d.crossCov(a, b));
    }
    // Direct check of one cross block against P (rows of 12, columns of 7).
    EXPECT_EQ(v.crossCov(12, 7), Eigen::Matrix2d(P.block(8, 3, 2, 2)));
}

TEST(EkfCovarianceView, HidesTentativeLandmarksUnlessAsked)
{
    hymm::ekf::EkfSlam::Options o;
    o.confirm_min_observations = 2;
    hymm::ekf::EkfSlam ekf(o);
    ekf.reset(Eigen::Vector3d::Zero(), 0.01 * Eigen::Matrix3d::Identity());
    hymm::ekf::RangeBearingObs z;
    z.z = Eigen::Vector2d(5.0, 0.3);
    z.R = Eigen::Vector2d(0.01, 0.001).asDiagonal();
    z.id = 4;
    ekf.updateRangeBearing({z}, mrpt::poses::CPose3D());
    ASSERT_TRUE(ekf.hasLandmark(4));
    ASSERT_FALSE(ekf.landmarkBlock(4).confirmed);

    EXPECT_FALSE(EkfCovarianceView(ekf).has(4));
    EXPECT_TRUE(EkfCovarianceView(ekf).ids().empty());
    const EkfCovarianceView all(ekf, false);
    EXPECT_TRUE(all.has(4));
    EXPECT_EQ(all.mean(4), ekf.landmarkMean(4));
    EXPECT_EQ(all.cov(4), ekf.landmarkCov(4));

    // The view is live: once confirmed, the default view shows it.
    ekf.updateRangeBearing({z}, mrpt::poses::CPose3D());
    ASSERT_TRUE(ekf.landmarkBlock(4).confirmed);
    EXPECT_TRUE(EkfCovarianceView(ekf).has(4));
}

TEST(EkfCovarianceView, IdsNearEqualsTheBruteForceFilterInStateOrder)
{
    // 60 points (ids 1000 - 3k, so state order differs from id order), one 3-DOF block
    // and one tentative landmark, which idsNear must hide like ids().
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-50, 50);
    std::vector<std::pair<long, int>> blocks;
    for (int k = 0; k < 60; ++k) blocks.emplace_back(1000 - 3 * k, 2);
    blocks.insert(blocks.begin() + 20, {5000, 3});
    const int n = 3 + 2 * 60 + 3;
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) x[i] = u(rng);
    hymm::ekf::EkfSlam::Options o;
    o.confirm_min_observations = 2;
    hymm::ekf::EkfSlam ekf(o);
    ekf.setActiveState(x, randomCov(n, 9), blocks);
    hymm::ekf::RangeBearingObs z;  // a tentative landmark at (5, 0) from the vehicle
    z.z = Eigen::Vector2d(5.0, 0.0);
    z.R = Eigen::Vector2d(0.01, 0.001).asDiagonal();
    z.id = 7;
    ekf.updateRangeBearing({z}, mrpt::poses::CPose3D());
    ASSERT_TRUE(ekf.hasLandmark(7));
    ASSERT_FALSE(ekf.landmarkBlock(7).confirmed);

    for (const bool confirmed_only : {true, false})
    {
        const EkfCovarianceView v(ekf, confirmed_only);
        size_t found = 0;
        for (int k = 0; k < 100; ++k)
        {
            const Eigen::Vector2d c(u(rng), u(rng));
            const double r = 0.4 * std::abs(u(rng));
            std::vector<long> brute;
            for (const long id : v.ids())
                if ((v.mean(id) - c).norm() <= r) brute.push_back(id);
            ASSERT_EQ(v.idsNear(c, r), brute);
            ASSERT_EQ(v.hymm::ltr::LandmarkCovarianceView::idsNear(c, r), brute);
            found += brute.size();
        }
        EXPECT_GT(found, 100u);
        const Eigen::Vector2d tentative = ekf.landmarkMean(7);
        const std::vector<long> at = v.idsNear(tentative, 1e-9);
        EXPECT_EQ(std::count(at.begin(), at.end(), 7L), confirmed_only ? 0 : 1);
    }
}

// Pose landmarks (x, y, phi) are hidden unless asked; then they are the point at their
// frame's origin, read in place like the points (thesis 6.2: regions on scan landmarks).
TEST(EkfCovarianceView, PoseLandmarksAreTheirFrameOriginWhenAsked)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-20, 20);
    const std::vector<std::pair<long, int>> blocks{{1, 2}, {2, 3}, {3, 2}};
    const int n = 3 + 2 + 3 + 2;
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) x[i] = u(rng);
    hymm::ekf::EkfSlam ekf{hymm::ekf::EkfSlam::Options{}};
    const Eigen::MatrixXd P = randomCov(n, 5);
    ekf.setActiveState(x, P, blocks);

    const EkfCovarianceView points(ekf);
    EXPECT_FALSE(points.has(2));
    EXPECT_EQ(points.ids(), (std::vector<long>{1, 3}));
    EXPECT_THROW(points.mean(2), std::out_of_range);

    const EkfCovarianceView all(ekf, true, true);
    EXPECT_TRUE(all.has(2));
    EXPECT_EQ(all.ids(), (std::vector<long>{1, 2, 3}));
    EXPECT_EQ(all.mean(2), x.segment<2>(5));  // after the vehicle (3) and landmark 1 (2)
    EXPECT_EQ(all.cov(2), Eigen::Matrix2d(P.block(5, 5, 2, 2)));
    EXPECT_EQ(all.crossCov(2, 3), Eigen::Matrix2d(P.block(5, 8, 2, 2)));
    EXPECT_EQ(all.crossVehicle(2), (Eigen::Matrix<double, 2, 3>(P.block(5, 0, 2, 3))));
    EXPECT_EQ(all.idsNear(x.segment<2>(5), 1e-9), std::vector<long>{2});

    // An auxiliary copy of pose landmark 2 (a scan template's apparent pose) is no vertex,
    // though it sits where landmark 2 does.
    const long aux = ekf.addBlockCopy(2, 0.01 * Eigen::Matrix3d::Identity());
    const EkfCovarianceView with_aux(ekf, true, true);
    EXPECT_FALSE(with_aux.has(aux));
    EXPECT_EQ(with_aux.ids(), (std::vector<long>{1, 2, 3}));
    EXPECT_EQ(with_aux.idsNear(x.segment<2>(5), 1e-9), std::vector<long>{2});
}

}  // namespace
