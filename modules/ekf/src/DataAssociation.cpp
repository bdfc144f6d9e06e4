#include "hymm/ekf/DataAssociation.h"

#include <mrpt/math/distributions.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

namespace hymm::ekf
{
namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();

/** Individual NIS (Eq. 2.58) and normalised distance N (Eq. 2.60) of every pairing. */
void individualDistances(const AssociationProblem& p, Eigen::MatrixXd& d2, Eigen::MatrixXd& nd)
{
    const size_t m = p.z.size(), k = p.h.size();
    d2.setConstant(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(k), kInf);
    nd = d2;
    for (size_t j = 0; j < k; ++j)
    {
        const auto jj = static_cast<Eigen::Index>(2 * j);
        const Eigen::Matrix2d Cj = p.C.block<2, 2>(jj, jj);
        for (size_t i = 0; i < m; ++i)
        {
            const Eigen::Matrix2d S = Cj + p.R[i];
            const double det = S.determinant();
            if (!(det > 0.0) || !(S(0, 0) > 0.0)) continue;  // not PD: leave +inf
            const Eigen::Vector2d nu = rangeBearingInnovation(p.z[i], p.h[j]);
            const double v = nu.dot(S.inverse() * nu);
            d2(i, j) = v;
            nd(i, j) = v + std::log(det);
        }
    }
}

std::vector<int> nearestNeighbour(const Eigen::MatrixXd& d2, const Eigen::MatrixXd& nd, double gate)
{
    // Greedy global NN: best normalised distance first, each landmark used once, so two
    // observations never update the same landmark in one batch.
    std::vector<std::tuple<double, int, int>> pairs;
    for (int i = 0; i < d2.rows(); ++i)
        for (int j = 0; j < d2.cols(); ++j)
            if (d2(i, j) < gate) pairs.emplace_back(nd(i, j), i, j);
    std::sort(pairs.begin(), pairs.end());
    std::vector<int> assign(static_cast<size_t>(d2.rows()), -1);
    std::vector<bool> used(static_cast<size_t>(d2.cols()), false);
    for (const auto& [dist, i, j] : pairs)
    {
        (void)dist;
        if (assign[static_cast<size_t>(i)] >= 0 || used[static_cast<size_t>(j)]) continue;
        assign[static_cast<size_t>(i)] = j;
        used[static_cast<size_t>(j)] = true;
    }
    return assign;
}

/**
 * JCBB with an incrementally extended Cholesky factor of the joint innovation
 * covariance: adding pairing (i, j) to a hypothesis of d pairings costs O(d^2)
 * instead of refactorising, and the joint NIS is the running sum |L^-1 nu|^2.
 */
class Jcbb
{
public:
    Jcbb(const AssociationProblem& p, const Eigen::MatrixXd& d2, double gate_prob, size_t max_nodes)
        : p_(p), gate_prob_(gate_prob), max_nodes_(max_nodes)
    {
        const size_t m = p.z.size();
        const double ind_gate = mrpt::math::chi2inv(gate_prob, 2);
        cand_.resize(m);
        for (size_t i = 0; i < m; ++i)
        {
            for (int j = 0; j < d2.cols(); ++j)
                if (d2(static_cast<Eigen::Index>(i), j) < ind_gate) cand_[i].push_back(j);
            // Most likely pairings first so good hypotheses are found early and prune more.
            std::sort(cand_[i].begin(), cand_[i].end(), [&](int a, int b) {
                return d2(static_cast<Eigen::Index>(i), a) < d2(static_cast<Eigen::Index>(i), b);
            });
        }
        joint_gate_.resize(m + 1, 0.0);
        for (size_t d = 1; d <= m; ++d)
            joint_gate_[d] = mrpt::math::chi2inv(gate_prob_, static_cast<unsigned>(2 * d));
        L_.setZero(static_cast<Eigen::Index>(2 * m), static_cast<Eigen::Index>(2 * m));
        y_.setZero(static_cast<Eigen::Index>(2 * m));
        cur_.assign(m, -1);
        best_ = cur_;
        used_.assign(p.h.size(), false);
        pair_obs_.reserve(m);
        pair_cand_.reserve(m);
    }

    void run(AssociationResult& out)
    {
        recurse(0, 0.0);
        out.assignment = best_;
        out.joint_nis = best_nis_;
        out.jcbb_nodes = nodes_;
        out.jcbb_truncated = truncated_;
    }

private:
    void recurse(size_t i, double nis)
    {
        if (max_nodes_ > 0 && nodes_ >= max_nodes_)
        {
            truncated_ = true;
            return;
        }
        ++nodes_;
        const size_t m = p_.z.size(), d = pair_obs_.size();
        if (i == m)
        {
            if (d > best_pairs_ || (d == best_pairs_ && nis < best_nis_))
            {
                best_pairs_ = d;
                best_nis_ = nis;
                best_ = cur_;
            }
            return;
        }
        for (int j : cand_[i])
        {
            if (used_[static_cast<size_t>(j)]) continue;
            double nis_new = 0.0;
            if (!extend(i, j, d, nis, nis_new) || !(nis_new < joint_gate_[d + 1])) continue;
            used_[static_cast<size_t>(j)] = true;
            cur_[i] = j;
            pair_obs_.push_back(i);
            pair_cand_.push_back(j);
            recurse(i + 1, nis_new);
            pair_obs_.pop_back();
            pair_cand_.pop_back();
            cur_[i] = -1;
            used_[static_cast<size_t>(j)] = false;
        }
        // Bound: leaving observation i unpaired can only help if the remaining
        // observations could still beat the best hypothesis.
        if (d + (m - i - 1) > best_pairs_) recurse(i + 1, nis);
    }

    /** Writes rows 2d, 2d+1 of L and y for pairing (i, j); false if not PD. */
    bool extend(size_t i, int j, size_t d, double nis, double& nis_new)
    {
        const auto e = static_cast<Eigen::Index>(2 * d);
        const auto jj = static_cast<Eigen::Index>(2 * j);
        Eigen::Matrix<double, Eigen::Dynamic, 2> B(e, 2);
        for (size_t a = 0; a < d; ++a)
            B.middleRows<2>(static_cast<Eigen::Index>(2 * a)) =
                p_.C.block<2, 2>(2 * static_cast<Eigen::Index>(pair_cand_[a]), jj);
        Eigen::Matrix<double, 2, Eigen::Dynamic> L21(2, e);
        if (e > 0)
            L21 = L_.topLeftCorner(e, e).triangularView<Eigen::Lower>().solve(B).transpose();
        const Eigen::Matrix2d D = p_.C.block<2, 2>(jj, jj) + p_.R[i] - L21 * L21.transpose();
        Eigen::LLT<Eigen::Matrix2d> llt(D);
        if (llt.info() != Eigen::Success) return false;
        const Eigen::Vector2d nu = rangeBearingInnovation(p_.z[i], p_.h[static_cast<size_t>(j)]);
        Eigen::Vector2d rhs = nu;
        if (e > 0) rhs -= L21 * y_.head(e);
        const Eigen::Vector2d y2 = llt.matrixL().solve(rhs);
        L_.block(e, 0, 2, e) = L21;
        L_.block<2, 2>(e, e) = llt.matrixL();
        y_.segment<2>(e) = y2;
        nis_new = nis + y2.squaredNorm();
        return std::isfinite(nis_new);
    }

    const AssociationProblem& p_;
    const double gate_prob_;
    const size_t max_nodes_;
    std::vector<std::vector<int>> cand_;
    std::vector<double> joint_gate_;
    Eigen::MatrixXd L_;
    Eigen::VectorXd y_;
    std::vector<int> cur_, best_;
    std::vector<bool> used_;
    std::vector<size_t> pair_obs_;
    std::vector<int> pair_cand_;
    size_t best_pairs_ = 0;
    double best_nis_ = 0.0;
    size_t nodes_ = 0;
    bool truncated_ = false;
};

}  // namespace

Eigen::Vector2d rangeBearingInnovation(const Eigen::Vector2d& z, const Eigen::Vector2d& h)
{
    return Eigen::Vector2d(z[0] - h[0], mrpt::math::wrapToPi(z[1] - h[1]));
}

AssociationResult associate(
    const AssociationProblem& problem, AssociationMethod method, double gate_prob,
    size_t jcbb_max_nodes)
{
    const size_t m = problem.z.size(), k = problem.h.size();
    if (problem.R.size() != m)
        throw std::invalid_argument("associate: one R per observation is required");
    if (problem.C.rows() != static_cast<Eigen::Index>(2 * k) || problem.C.cols() != problem.C.rows())
        throw std::invalid_argument("associate: C must be 2k x 2k for k candidates");
    if (!(gate_prob > 0.0 && gate_prob < 1.0))
        throw std::invalid_argument("associate: gate_prob must be in (0, 1)");

    AssociationResult out;
    Eigen::MatrixXd nd;
    individualDistances(problem, out.d2, nd);
    out.assignment.assign(m, -1);
    if (m == 0 || k == 0) return out;

    if (method == AssociationMethod::NearestNeighbour)
    {
        out.assignment = nearestNeighbour(out.d2, nd, mrpt::math::chi2inv(gate_prob, 2));
        for (size_t i = 0; i < m; ++i)
            if (out.assignment[i] >= 0)
                out.joint_nis += out.d2(static_cast<Eigen::Index>(i), out.assignment[i]);
        return out;
    }
    Jcbb(problem, out.d2, gate_prob, jcbb_max_nodes).run(out);
    return out;
}

}  // namespace hymm::ekf
