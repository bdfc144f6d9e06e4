// hymm::ekf::associate against MRPT's mrpt::slam::data_association_full_covariance (the
// association of CRangeBearingKFSLAM2D) on the same range-bearing problems, NN and JCBB,
// the same 0.99 gate. A problem: the vehicle estimate off its truth by a draw of its
// covariance, 8 landmarks (estimates 0.1 m off, independent of the vehicle) 2-12 m
// away and 2 clutter returns; C = H P H^T with the vehicle cross terms. MRPT takes one
// covariance per prediction, so it gets C + blockdiag(R) (the same R for every
// observation, as its filter adds it). Problems are built outside the timed region.
//
// Counters (over the 200 problems, seeds 1-200): `correct` / `wrong` = fraction of the
// observations paired with their true landmark / with another landmark or paired while
// clutter; `agree` (MRPT's runs) = fraction of the observations both assign alike.
// Scenes: 0 = landmarks ahead (bearings within +-90 deg), vehicle sigma 0.3 m / 3 deg;
// 1 = the same with sigma 1 m / 8 deg (where joint compatibility matters);
// 2 = landmarks behind the vehicle (bearings near +-180 deg), sigma 0.3 m / 3 deg.
//
// Run: build/benchmarks/data_association_vs_mrpt_bench
#include <benchmark/benchmark.h>
#include <hymm/core/RangeBearingModel.h>
#include <hymm/ekf/DataAssociation.h>
#include <mrpt/math/CMatrixDynamic.h>
#include <mrpt/slam/data_association.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace
{
using hymm::ekf::AssociationMethod;

constexpr size_t kProblems = 200, kLandmarks = 8, kClutter = 2;
constexpr double kGate = 0.99;

struct Problem
{
    hymm::ekf::AssociationProblem ours;
    mrpt::math::CMatrixDouble Z, Y, YC;  // MRPT's inputs
    std::vector<int> truth;              // per observation: landmark index, -1 clutter
};

Problem makeProblem(unsigned seed, int scene)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> n01(0.0, 1.0);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const double s_xy = scene == 1 ? 1.0 : 0.3, s_phi = (scene == 1 ? 8.0 : 3.0) * M_PI / 180;
    const double s_l = 0.1, s_r = 0.05, s_b = M_PI / 180;
    const Eigen::Vector3d truth_v(0, 0, 0), sensor(0, 0, 0);
    const Eigen::Vector3d est_v(s_xy * n01(rng), s_xy * n01(rng), s_phi * n01(rng));
    const Eigen::Matrix3d Pv = Eigen::Vector3d(s_xy * s_xy, s_xy * s_xy, s_phi * s_phi).asDiagonal();
    Eigen::Matrix2d R = Eigen::Vector2d(s_r * s_r, s_b * s_b).asDiagonal();

    // True landmarks at least 1 m apart; bearings ahead or around +-180 deg.
    std::vector<Eigen::Vector2d> lm;
    while (lm.size() < kLandmarks)
    {
        const double r = 2 + 10 * u01(rng);
        const double b = scene == 2 ? M_PI + (u01(rng) - 0.5) * M_PI / 2 : (u01(rng) - 0.5) * M_PI;
        const Eigen::Vector2d p(r * std::cos(b), r * std::sin(b));
        if (std::all_of(lm.begin(), lm.end(), [&](const auto& q) { return (q - p).norm() > 1.0; }))
            lm.push_back(p);
    }
    Problem pr;
    const size_t k = lm.size();
    Eigen::MatrixXd Hv(2 * k, 3);
    pr.ours.C = Eigen::MatrixXd::Zero(2 * static_cast<Eigen::Index>(k), 2 * static_cast<Eigen::Index>(k));
    for (size_t j = 0; j < k; ++j)
    {
        const Eigen::Vector2d est_l = lm[j] + s_l * Eigen::Vector2d(n01(rng), n01(rng));
        hymm::core::Mat23 H_v;
        hymm::core::Mat2 H_l;
        pr.ours.h.push_back(hymm::core::observeRangeBearing(est_v, sensor, est_l, &H_v, &H_l));
        Hv.middleRows<2>(2 * static_cast<Eigen::Index>(j)) = H_v;
        pr.ours.C.block<2, 2>(2 * static_cast<Eigen::Index>(j), 2 * static_cast<Eigen::Index>(j)) =
            s_l * s_l * H_l * H_l.transpose();
    }
    pr.ours.C += Hv * Pv * Hv.transpose();
    // Observations in a random order: every landmark, then clutter.
    std::vector<int> order(k + kClutter);
    for (size_t i = 0; i < order.size(); ++i) order[i] = i < k ? static_cast<int>(i) : -1;
    std::shuffle(order.begin(), order.end(), rng);
    for (int j : order)
    {
        Eigen::Vector2d z;
        if (j >= 0)
            z = hymm::core::observeRangeBearing(truth_v, sensor, lm[static_cast<size_t>(j)]) +
                Eigen::Vector2d(s_r * n01(rng), s_b * n01(rng));
        else
            z = Eigen::Vector2d(2 + 10 * u01(rng), scene == 2 ? M_PI * (2 * u01(rng) - 1) : (u01(rng) - 0.5) * M_PI);
        z[1] = std::atan2(std::sin(z[1]), std::cos(z[1]));
        pr.ours.z.push_back(z);
        pr.ours.R.push_back(R);
        pr.truth.push_back(j);
    }
    const size_t m = pr.ours.z.size();
    pr.Z.resize(m, 2);
    pr.Y.resize(k, 2);
    for (size_t i = 0; i < m; ++i) pr.Z(i, 0) = pr.ours.z[i][0], pr.Z(i, 1) = pr.ours.z[i][1];
    for (size_t j = 0; j < k; ++j) pr.Y(j, 0) = pr.ours.h[j][0], pr.Y(j, 1) = pr.ours.h[j][1];
    Eigen::MatrixXd yc = pr.ours.C;
    for (size_t j = 0; j < k; ++j) yc.block<2, 2>(2 * static_cast<Eigen::Index>(j), 2 * static_cast<Eigen::Index>(j)) += R;
    pr.YC = mrpt::math::CMatrixDouble(yc);
    return pr;
}

const std::vector<Problem>& problems(int scene)
{
    static std::vector<std::vector<Problem>> all(3);
    auto& v = all[static_cast<size_t>(scene)];
    if (v.empty())
        for (unsigned s = 1; s <= kProblems; ++s) v.push_back(makeProblem(s, scene));
    return v;
}

std::vector<int> ours(const Problem& p, AssociationMethod m) { return hymm::ekf::associate(p.ours, m, kGate).assignment; }

std::vector<int> mrpts(const Problem& p, mrpt::slam::TDataAssociationMethod m)
{
    mrpt::slam::TDataAssociationResults r;
    mrpt::slam::data_association_full_covariance(p.Z, p.Y, p.YC, r, m, mrpt::slam::metricMaha, kGate);
    std::vector<int> a(p.truth.size(), -1);
    for (const auto& [i, j] : r.associations) a[i] = static_cast<int>(j);
    return a;
}

/** Sets correct / wrong (and agree, when `other` is given) over every problem. */
template <class F, class G>
void score(benchmark::State& st, const std::vector<Problem>& ps, F assoc, G other)
{
    double n = 0, correct = 0, wrong = 0, agree = 0;
    for (const auto& p : ps)
    {
        const auto a = assoc(p), b = other(p);
        for (size_t i = 0; i < a.size(); ++i)
        {
            ++n;
            correct += a[i] >= 0 && a[i] == p.truth[i];
            wrong += a[i] >= 0 && a[i] != p.truth[i];
            agree += a[i] == b[i];
        }
    }
    st.counters["correct"] = correct / n;
    st.counters["wrong"] = wrong / n;
    st.counters["agree"] = agree / n;
}

template <bool kMrpt, bool kJcbb>
void BM_Associate(benchmark::State& st)
{
    const auto& ps = problems(static_cast<int>(st.range(0)));
    const auto ourMethod = kJcbb ? AssociationMethod::JCBB : AssociationMethod::NearestNeighbour;
    const auto theirMethod = kJcbb ? mrpt::slam::assocJCBB : mrpt::slam::assocNN;
    auto run_ours = [&](const Problem& p) { return ours(p, ourMethod); };
    auto run_mrpt = [&](const Problem& p) { return mrpts(p, theirMethod); };
    if (kMrpt)
        score(st, ps, run_mrpt, run_ours);
    else
        score(st, ps, run_ours, run_mrpt);
    size_t i = 0;
    for (auto _ : st)
    {
        const auto& p = ps[i++ % ps.size()];
        if (kMrpt)
            benchmark::DoNotOptimize(run_mrpt(p));
        else
            benchmark::DoNotOptimize(run_ours(p));
    }
}

}  // namespace

BENCHMARK_TEMPLATE(BM_Associate, false, false)->Name("HymmNN")->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Associate, true, false)->Name("MrptNN")->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Associate, false, true)->Name("HymmJCBB")->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Associate, true, true)->Name("MrptJCBB")->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
