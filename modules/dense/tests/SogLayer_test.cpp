/**
 * @file SogLayer_test.cpp
 * @brief SOG observation covariance (Eq. 4.15-4.16) in a deformed region, the two
 *        fusion rules against their closed forms, nearest-neighbour association and
 *        the surface / ellipse outputs.
 */
#include "hymm/dense/SogLayer.h"

#include <gtest/gtest.h>
#include <iostream>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/num_jacobian.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>

namespace
{
using namespace hymm::dense;
using V2 = Eigen::Vector2d;
using M2 = Eigen::Matrix2d;
using G = SogLayer::Gaussian;

SogLayer::Options opts(SogLayer::FusionRule rule = SogLayer::FusionRule::Average)
{
    SogLayer::Options o;
    o.fusion_rule = rule;
    return o;
}

M2 spd(double a, double b, double c)
{
    M2 m;
    m << a, b, b, c;
    return m;
}

void expectCovariance(const M2& p)
{
    EXPECT_EQ(p(0, 1), p(1, 0));
    const Eigen::SelfAdjointEigenSolver<M2> es(p);
    EXPECT_GE(es.eigenvalues().minCoeff(), 0.0);
}

TEST(SogLayerTest, ObservationCovarianceIsNumericJacobianPropagationInTheReferenceFrame)
{
    // Region deformed since creation: current = A reference + t.
    M2 a;
    a << 1.05, 0.1, -0.08, 0.97;
    RegionScan scan;
    scan.to_reference_linear = a.inverse();
    scan.sensor = V2(1, 2);  // reference coordinates
    scan.range_std_m = 0.07;
    scan.bearing_std_rad = 0.02;
    scan.hits = {V2(6, 4), V2(-3, 7)};
    SogLayer layer(opts());
    const auto gs = layer.observationGaussians(scan);
    ASSERT_EQ(gs.size(), 2u);
    for (size_t k = 0; k < 2; ++k)
    {
        // Polar measurement in the current (metric) frame, then the numeric Jacobian of
        // reference position w.r.t. (r, theta): x_ref = s_ref + A^{-1} (r cos t, r sin t).
        const V2 d = a * (scan.hits[k] - scan.sensor);
        Eigen::VectorXd z(2), inc(2);
        z << d.norm(), std::atan2(d.y(), d.x());
        inc << 1e-6, 1e-7;
        const std::function<void(const Eigen::VectorXd&, const int&, Eigen::VectorXd&)> f =
            [&](const Eigen::VectorXd& zz, const int&, Eigen::VectorXd& out) {
                out = scan.sensor + a.inverse() * V2(zz[0] * std::cos(zz[1]), zz[0] * std::sin(zz[1]));
            };
        Eigen::MatrixXd j;
        mrpt::math::estimateJacobian(z, f, inc, 0, j);
        const M2 r = V2(0.07 * 0.07, 0.02 * 0.02).asDiagonal();
        const M2 expected = j * r * j.transpose();
        EXPECT_LT((gs[k].cov - expected).norm(), 1e-9) << gs[k].cov << "\n" << expected;
        EXPECT_LT((gs[k].mean - scan.hits[k]).norm(), 1e-12);
        expectCovariance(gs[k].cov);
    }
}

TEST(SogLayerTest, AverageFusionFollowsEquations417To420)
{
    SogLayer layer(opts());  // d_min 0.2, k 0.8: threshold 0.16 m
    const G a{V2(1, 2), spd(0.002, 0.0005, 0.003)};
    const G b{V2(1.1, 2.05), spd(0.004, -0.001, 0.001)};
    ASSERT_LE(majorSigma(a.cov) + majorSigma(b.cov), 0.16);
    const G small = layer.fuse(a, b);
    EXPECT_LT((small.mean - V2(1.05, 2.025)).norm(), 1e-15);  // Eq. 4.17
    EXPECT_LT((small.cov - (a.cov + b.cov)).norm(), 1e-15);    // Eq. 4.19
    const G big{V2(1.1, 2.05), spd(0.04, 0.0, 0.01)};
    ASSERT_GT(majorSigma(a.cov) + majorSigma(big.cov), 0.16);
    const G kept = layer.fuse(a, big);
    EXPECT_LT((kept.mean - V2(1.05, 2.025)).norm(), 1e-15);
    EXPECT_EQ(kept.cov, a.cov);  // Eq. 4.20
    // sigma of Eq. 4.18 is the major 1-sigma semi-axis.
    EXPECT_NEAR(majorSigma(spd(0.04, 0.0, 0.01)), 0.2, 1e-15);
}

TEST(SogLayerTest, ProductFusionEqualsClosedFormGaussianProduct)
{
    SogLayer layer(opts(SogLayer::FusionRule::Product));
    const G a{V2(1, 2), spd(0.02, 0.005, 0.03)};
    const G b{V2(1.1, 1.95), spd(0.04, -0.01, 0.01)};
    const G c = layer.fuse(a, b);
    const M2 s = (a.cov.inverse() + b.cov.inverse()).inverse();
    const V2 m = s * (a.cov.inverse() * a.mean + b.cov.inverse() * b.mean);
    EXPECT_LT((c.cov - s).norm(), 1e-12);
    EXPECT_LT((c.mean - m).norm(), 1e-12);
    expectCovariance(c.cov);
    // The product density is proportional to g(x; a) g(x; b) everywhere.
    const auto g = [](const G& q, const V2& x) {
        const V2 d = x - q.mean;
        return std::exp(-0.5 * d.dot(q.cov.inverse() * d)) / (2 * M_PI * std::sqrt(q.cov.determinant()));
    };
    const double k0 = g(a, V2(1, 2)) * g(b, V2(1, 2)) / g(c, V2(1, 2));
    for (const V2& x : {V2(0.9, 2.1), V2(1.2, 1.8), V2(1.05, 1.99)})
        EXPECT_NEAR(g(a, x) * g(b, x) / g(c, x), k0, 1e-9 * k0);
}

RegionScan wallScan(double wall_x, double jitter)
{
    RegionScan s;
    s.sensor = V2(0, 0);
    // 2 deg apart: neighbouring returns 0.17 m apart at 5 m, so a return's nearest map
    // Gaussian is its own beam's (jitter <= 0.03 m).
    for (int k = -10; k <= 10; ++k)
    {
        const double th = k * 2.0 * M_PI / 180;
        const double r = wall_x / std::cos(th) + jitter;
        s.hits.emplace_back(r * std::cos(th), r * std::sin(th));
    }
    return s;
}

TEST(SogLayerTest, RepeatedScansFuseInsteadOfGrowing)
{
    SogLayer layer(opts());
    layer.insert(wallScan(5.0, 0.0));
    const size_t n = layer.size();
    EXPECT_EQ(n, 21u);
    for (int rep = 0; rep < 5; ++rep) layer.insert(wallScan(5.0, rep % 2 ? 0.03 : -0.03));
    EXPECT_EQ(layer.size(), n);  // every return lands within d_min of its Gaussian
    for (const G& g : layer.gaussians())
    {
        EXPECT_NEAR(g.mean.x(), 5.0, 0.05);
        expectCovariance(g.cov);
    }
    // A second wall beyond d_min adds its own Gaussians.
    layer.insert(wallScan(7.0, 0.0));
    EXPECT_EQ(layer.size(), 2 * n);
}

TEST(SogLayerTest, ReturnsBeyondMaxRangeAddNoGaussian)
{
    // The wall at 5 m, returns every 2 deg: within 5.1 m of the sensor are the 11 of
    // +-10 deg (5.077 m at 10 deg, 5.112 m at 12 deg).
    SogLayer::Options o = opts();
    o.max_range_m = 5.1;
    SogLayer layer(o);
    layer.insert(wallScan(5.0, 0.0));
    ASSERT_EQ(layer.size(), 11u);
    for (const G& g : layer.gaussians()) EXPECT_LE(g.mean.norm(), 5.1);
    // The range is measured in the current (metric) frame: a region that has grown to
    // twice its reference size sees the same returns at twice the range.
    RegionScan grown = wallScan(5.0, 0.0);
    grown.to_reference_linear = 0.5 * M2::Identity();
    SogLayer at_5_1(o);
    at_5_1.insert(grown);
    EXPECT_EQ(at_5_1.size(), 0u);
    o.max_range_m = 10.2;
    SogLayer at_10_2(o);
    at_10_2.insert(grown);
    EXPECT_EQ(at_10_2.size(), 11u);
    // 0 keeps every return (the thesis); a negative or NaN range is a configuration error.
    o.max_range_m = 0;
    SogLayer all(o);
    all.insert(wallScan(5.0, 0.0));
    EXPECT_EQ(all.size(), 21u);
    o.max_range_m = -1;
    EXPECT_THROW(SogLayer{o}, std::invalid_argument);
    o.max_range_m = std::nan("");
    EXPECT_THROW(SogLayer{o}, std::invalid_argument);
}

TEST(SogLayerTest, RevisitsAreAbsorbedWithinDMin)
{
    // Returns 0.5 deg apart (0.04 m at 5 m), each revisit with its beams shifted along
    // the wall: several returns per map Gaussian. The thesis step fuses one per map
    // Gaussian and adds the others, on every revisit; absorbing them (the default) adds
    // nothing once the wall is mapped.
    auto o = opts();
    std::mt19937_64 rng(3);
    std::normal_distribution<double> noise(0.0, 0.03);
    std::uniform_real_distribution<double> shift(0.0, 0.5);
    const auto dense_wall = [&](int) {
        RegionScan s;
        s.sensor = V2(0, 0);
        const double offset = shift(rng);
        for (int k = -40; k <= 40; ++k)
        {
            const double th = (k * 0.5 + offset) * M_PI / 180;
            const double r = 5.0 / std::cos(th) + noise(rng);
            s.hits.emplace_back(r * std::cos(th), r * std::sin(th));
        }
        return s;
    };
    o.merge_within_m = 0;  // absorbing alone (merging: the next test)
    o.max_mean_per_cell = 0;
    o.absorb_within_d_min = true;
    SogLayer absorb(o);
    o.absorb_within_d_min = false;
    SogLayer thesis(o);
    std::vector<size_t> n_absorb, n_thesis;
    for (int rep = 0; rep < 20; ++rep)
    {
        const RegionScan scan = dense_wall(rep);
        absorb.insert(scan);
        thesis.insert(scan);
        n_absorb.push_back(absorb.size());
        n_thesis.push_back(thesis.size());
    }
    EXPECT_EQ(n_absorb.front(), 81u);  // an empty map absorbs nothing
    EXPECT_EQ(n_absorb.back(), n_absorb.front());
    EXPECT_GT(n_thesis.back(), n_thesis.front() + 10);
    for (const G& g : absorb.gaussians())
    {
        EXPECT_NEAR(g.mean.x(), 5.0, 0.05);
        expectCovariance(g.cov);
    }
}

/** Scans of the wall x = 5 seen from the origin (+-20 deg, 81 beams at a random bearing
 *  offset) with Gaussian range noise of `std_m`; the same seed gives the same scans. */
struct NoisyWall
{
    std::mt19937_64 rng{11};
    std::normal_distribution<double> noise;
    std::uniform_real_distribution<double> shift{0.0, 0.5};
    explicit NoisyWall(double std_m) : noise(0.0, std_m) {}
    RegionScan operator()()
    {
        RegionScan s;
        s.sensor = V2(0, 0);
        const double offset = shift(rng);
        for (int k = -40; k <= 40; ++k)
        {
            const double th = (k * 0.5 + offset) * M_PI / 180;
            const double r = 5.0 / std::cos(th) + noise(rng);
            s.hits.emplace_back(r * std::cos(th), r * std::sin(th));
        }
        return s;
    }
};

TEST(SogLayerTest, RevisitsMergeComponentsThatDriftTogether)
{
    // Many revisits of a wall with noise of half d_min: the tails keep giving birth to
    // components beyond d_min of the map, and the fused means wander. Absorbing alone
    // keeps adding components; merging the moved ones that come within d_min / 2 of
    // another levels the count off.
    auto o = opts();
    NoisyWall wall(0.5 * o.d_min_m);
    o.absorb_within_d_min = true;
    o.max_mean_per_cell = 0;  // the cap: RevisitsCapComponentsPerRegionAndStayOnTheSurface
    o.merge_within_m = 0.5 * o.d_min_m;
    SogLayer merge(o);
    o.merge_within_m = 0;
    SogLayer absorb(o);
    std::vector<size_t> n_merge, n_absorb;
    for (int rep = 0; rep < 400; ++rep)
    {
        const RegionScan scan = wall();
        merge.insert(scan);
        absorb.insert(scan);
        n_merge.push_back(merge.size());
        n_absorb.push_back(absorb.size());
    }
    EXPECT_EQ(n_merge.front(), n_absorb.front());  // a first visit merges nothing
    // Absorbing alone: still growing over the last 200 revisits.
    EXPECT_GT(n_absorb[399], n_absorb[199] + 20);
    // Merging: levelled off (the last 200 revisits add at most a few components) and
    // below absorbing alone.
    EXPECT_LE(n_merge[399], n_merge[199] + 5);
    EXPECT_LT(n_merge[399], n_absorb[399]);
    // The surface is no further from the wall than with absorbing alone.
    const auto meanError = [](const SogLayer& l) {
        double err = 0;
        for (const G& g : l.gaussians())
        {
            err += std::abs(g.mean.x() - 5.0);
            expectCovariance(g.cov);
        }
        return err / l.size();
    };
    std::cout << "components after 200 / 400 revisits: merging " << n_merge[199] << " / " << n_merge[399]
              << ", absorbing alone " << n_absorb[199] << " / " << n_absorb[399] << "; mean distance from the wall "
              << meanError(merge) << " / " << meanError(absorb) << " m\n";
    // The price (why merging is off by default): fewer components, each moved halfway to
    // every return of a wider area (Eq. 4.17), sit about as far from the wall as the raw
    // returns (0.080 m here), twice as far as with absorbing alone.
    EXPECT_LT(meanError(merge), 2.5 * meanError(absorb));
    EXPECT_LT(meanError(merge), 0.5 * o.d_min_m);
}

TEST(SogLayerTest, MergeKeepsTheMomentsOfTheDrawnPair)
{
    // Ground truth: the mean and covariance of the surface the pair draws (two peak-1
    // Gaussians summed, Fig. 4.12 b), integrated on a fine grid.
    const G a{V2(1.0, 2.0), spd(0.010, 0.002, 0.004)};
    const G b{V2(1.15, 1.9), spd(0.003, -0.001, 0.006)};
    const G m = mergeMoments(a, b);
    const auto peak1 = [](const G& g, const V2& x) {
        const V2 d = x - g.mean;
        return std::exp(-0.5 * d.dot(g.cov.inverse() * d));
    };
    double mass = 0;
    V2 mean = V2::Zero();
    M2 second = M2::Zero();
    const double h = 0.004;
    for (double x = 0.4; x < 1.8; x += h)
        for (double y = 1.3; y < 2.6; y += h)
        {
            const V2 p(x, y);
            const double f = peak1(a, p) + peak1(b, p);
            mass += f;
            mean += f * p;
            second += f * p * p.transpose();
        }
    mean /= mass;
    const M2 cov = second / mass - mean * mean.transpose();
    EXPECT_LT((m.mean - mean).norm(), 1e-6) << m.mean.transpose() << " / " << mean.transpose();
    EXPECT_LT((m.cov - cov).norm(), 1e-6) << m.cov << "\n" << cov;
    expectCovariance(m.cov);
}

TEST(SogLayerTest, RevisitsAreBoundedByTheAreaAndStayOnTheSurface)
{
    // 400 revisits of a wall with noise of half d_min (as above): absorbing alone keeps
    // adding components; the bound (the default max_mean_per_cell) merges the closest
    // pairs once the region holds more than 3 per d_min cell its means occupy, so the
    // count levels off, and the mixture still lies on, and covers, the wall.
    auto o = opts();
    NoisyWall wall(0.5 * o.d_min_m);
    o.merge_within_m = 0;
    ASSERT_EQ(o.max_mean_per_cell, 3.0);  // the default
    SogLayer capped(o);
    o.max_mean_per_cell = 0;
    SogLayer absorb(o);
    size_t first_capped = 0;
    std::vector<size_t> n_capped, n_absorb;
    std::vector<double> raw;  // the returns' distances from the wall
    for (int rep = 0; rep < 400; ++rep)
    {
        const RegionScan scan = wall();
        capped.insert(scan);
        absorb.insert(scan);
        if (rep == 0)
        {
            first_capped = capped.size();
            // A first visit below the cap is the thesis' (bit for bit).
            ASSERT_EQ(capped.size(), absorb.size());
            for (size_t i = 0; i < capped.size(); ++i) ASSERT_EQ(capped.gaussians()[i].mean, absorb.gaussians()[i].mean);
        }
        n_capped.push_back(capped.size());
        n_absorb.push_back(absorb.size());
        for (const V2& h : scan.hits) raw.push_back(std::abs(h.x() - 5.0));
    }
    EXPECT_EQ(first_capped, 81u);
    // Absorbing alone: still growing over the last 200 revisits (182 -> 292).
    EXPECT_GT(n_absorb[399], n_absorb[199] + 50);
    // The bound: levelled off (111 at 200 and at 400 revisits), well below.
    EXPECT_LE(n_capped[399], n_capped[199] + 5);
    EXPECT_LT(n_capped[399], 150u);
    const auto distances = [](const SogLayer& l) {
        std::vector<double> d;
        for (const G& g : l.gaussians())
        {
            d.push_back(std::abs(g.mean.x() - 5.0));
            expectCovariance(g.cov);
        }
        std::sort(d.begin(), d.end());
        return d;
    };
    const auto mean = [](const std::vector<double>& d) { return std::accumulate(d.begin(), d.end(), 0.0) / d.size(); };
    const auto dc = distances(capped), da = distances(absorb);
    std::cout << "components after 200 / 400 revisits: bound " << n_capped[199] << " / " << capped.size() << ", absorbing alone " << absorb.size()
              << "; mean / 95th percentile distance from the wall " << mean(dc) << " / " << dc[dc.size() * 95 / 100]
              << " against " << mean(da) << " / " << da[da.size() * 95 / 100] << " m, the returns " << mean(raw)
              << " m\n";
    // Fewer components each fuse more returns per scan, and Eq. 4.17 moves a component
    // halfway to each: the capped means sit a little further from the wall than with
    // absorbing alone (0.054 against 0.041 m here; merge_within_m 0.1 m: 0.080), well
    // inside the returns' spread (0.080 m).
    EXPECT_LT(mean(dc), 1.4 * mean(da));
    EXPECT_LT(mean(dc), 0.75 * mean(raw));
    // The wall stays covered: the drawn surface (peak-1 Gaussians) is high all along it.
    ScalarField f;
    f.origin = V2(4.9, -1.6);
    f.resolution = 0.05;
    f.values = Eigen::MatrixXd::Zero(64, 4);
    capped.addSurface(hymm::ltr::AffineRegionMap(), f);
    for (int iy = 0; iy < f.sizeY(); ++iy) EXPECT_GT(f.values.row(iy).maxCoeff(), 0.5) << "y " << f.cellCentre(0, iy).y();
}

TEST(SogLayerTest, SurfaceEllipsesAndRendering)
{
    SogLayer layer(opts());
    RegionScan s;
    s.sensor = V2(0, 0);
    s.hits = {V2(4, 3)};
    layer.insert(s);
    ASSERT_EQ(layer.size(), 1u);
    const G& g = layer.gaussians()[0];
    const hymm::ltr::AffineRegionMap id;
    // Peak-1 Gaussian: 1 at the mean, exp(-1/2) one sigma along an eigenvector.
    ScalarField f;
    f.origin = V2(4, 3) - V2(0.0005, 0.0005);
    f.resolution = 0.001;
    f.values = Eigen::MatrixXd::Zero(1, 1);
    layer.addSurface(id, f);
    EXPECT_NEAR(f.values(0, 0), 1.0, 1e-12);
    const Eigen::SelfAdjointEigenSolver<M2> es(g.cov);
    const V2 one_sigma = g.mean + std::sqrt(es.eigenvalues()(1)) * es.eigenvectors().col(1);
    f.origin = one_sigma - V2(0.0005, 0.0005);
    f.values.setZero();
    layer.addSurface(id, f);
    EXPECT_NEAR(f.values(0, 0), std::exp(-0.5), 1e-9);

    const auto ells = layer.ellipses(id, 24);
    ASSERT_EQ(ells.size(), 1u);
    for (const V2& p : ells[0]) EXPECT_NEAR((p - g.mean).dot(g.cov.inverse() * (p - g.mean)), 1.0, 1e-9);

    mrpt::maps::CSimplePointsMap pts;
    layer.renderInto(id, pts);
    ASSERT_EQ(pts.size(), 1u);
    EXPECT_NEAR(pts.getPointsBufferRef_x()[0], 4.0, 1e-5);
    mrpt::maps::COccupancyGridMap2D og(2, 6, 1, 5, 0.05f);
    og.fill(0.0f);
    layer.renderInto(id, og);
    EXPECT_GT(og.getPos(4.0f, 3.0f), 0.9f);
    EXPECT_LT(og.getPos(3.0f, 2.0f), 0.05f);
}

TEST(SogLayerTest, SaveLoadRoundTripAndBadInput)
{
    SogLayer layer(opts());
    layer.insert(wallScan(5.0, 0.0));
    std::stringstream ss;
    layer.save(ss);
    SogLayer copy(opts());
    copy.load(ss);
    ASSERT_EQ(copy.size(), layer.size());
    for (size_t i = 0; i < copy.size(); ++i)
    {
        EXPECT_EQ(copy.gaussians()[i].mean, layer.gaussians()[i].mean);
        EXPECT_EQ(copy.gaussians()[i].cov, layer.gaussians()[i].cov);
    }
    std::stringstream bad("sog 1\n0x1p+0 0x1p+0 -0x1p+0 0x0p+0 0x1p+0\n");  // negative variance
    EXPECT_THROW(copy.load(bad), std::runtime_error);
    EXPECT_EQ(copy.size(), layer.size());  // unchanged on failure

    RegionScan s = wallScan(5.0, 0.0);
    s.range_std_m = std::nan("");
    EXPECT_THROW(layer.insert(s), std::invalid_argument);
    s = wallScan(5.0, 0.0);
    s.hits[3].x() = std::nan("");
    EXPECT_THROW(layer.insert(s), std::invalid_argument);
}

}  // namespace
