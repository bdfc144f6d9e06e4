#include "hymm/ekf/PassiveStates.h"

#include <stdexcept>
#include <string>

#include "se2_retraction.h"

namespace hymm::ekf
{
namespace
{
/** Removes rows [r, r + d) of a dense matrix. */
void eraseRows(Eigen::MatrixXd& A, Eigen::Index r, Eigen::Index d)
{
    const Eigen::Index tail = A.rows() - r - d;
    if (tail > 0) A.middleRows(r, tail) = A.bottomRows(tail).eval();
    A.conservativeResize(A.rows() - d, Eigen::NoChange);
}
}  // namespace

void PassiveStates::add(long id, const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov,
                        const Eigen::MatrixXd& cross, size_t n_active)
{
    const auto d = mean.size();
    const std::string who = "PassiveStates::add(id=" + std::to_string(id) + "): ";
    if (id < 0) throw std::invalid_argument(who + "negative id");
    if (has(id)) throw std::invalid_argument(who + "id already exists");
    if (d < 1) throw std::invalid_argument(who + "empty mean");
    if (cov.rows() != d || cov.cols() != d)
        throw std::invalid_argument(who + "cov must be dim x dim");
    if (cross.rows() != d || cross.cols() != static_cast<Eigen::Index>(n_active))
        throw std::invalid_argument(who + "cross must be dim x n_active");
    if (!mean.allFinite() || !cov.allFinite() || !cross.allFinite())
        throw std::invalid_argument(who + "non-finite input");
    if ((cov - cov.transpose()).cwiseAbs().maxCoeff() > 1e-9 * (1.0 + cov.cwiseAbs().maxCoeff()))
        throw std::invalid_argument(who + "cov is not symmetric");

    Block b{id, static_cast<int>(d), static_cast<size_t>(mean_.size())};
    const Eigen::Index rows = mean_.size();
    mean_.conservativeResize(rows + d);
    mean_.tail(d) = mean;
    if (rows == 0) cross_.resize(0, static_cast<Eigen::Index>(n_active));
    cross_.conservativeResize(rows + d, Eigen::NoChange);
    cross_.bottomRows(d) = cross;
    own_.push_back(0.5 * (cov + cov.transpose()));
    index_[id] = blocks_.size();
    blocks_.push_back(b);
}

void PassiveStates::remove(long id)
{
    const auto it = index_.find(id);
    if (it == index_.end())
        throw std::out_of_range("PassiveStates::remove: unknown id " + std::to_string(id));
    const size_t pos = it->second;
    const Block b = blocks_[pos];
    const auto r = static_cast<Eigen::Index>(b.row), d = static_cast<Eigen::Index>(b.dim);
    const Eigen::Index tail = mean_.size() - r - d;
    if (tail > 0) mean_.segment(r, tail) = mean_.tail(tail).eval();
    mean_.conservativeResize(mean_.size() - d);
    eraseRows(cross_, r, d);
    blocks_.erase(blocks_.begin() + static_cast<std::ptrdiff_t>(pos));
    own_.erase(own_.begin() + static_cast<std::ptrdiff_t>(pos));
    index_.erase(it);
    for (size_t k = pos; k < blocks_.size(); ++k)
    {
        blocks_[k].row -= static_cast<size_t>(d);
        index_[blocks_[k].id] = k;
    }
}

std::vector<long> PassiveStates::ids() const
{
    std::vector<long> out;
    for (const auto& b : blocks_) out.push_back(b.id);
    return out;
}

const PassiveStates::Block& PassiveStates::block(long id) const
{
    const auto it = index_.find(id);
    if (it == index_.end())
        throw std::out_of_range("PassiveStates: unknown passive id " + std::to_string(id));
    return blocks_[it->second];
}

Eigen::VectorXd PassiveStates::mean(long id) const
{
    const Block& b = block(id);
    return mean_.segment(static_cast<Eigen::Index>(b.row), b.dim);
}

Eigen::MatrixXd PassiveStates::cov(long id) const
{
    block(id);  // throws a clear error if unknown
    return own_[index_.at(id)];
}

Eigen::MatrixXd PassiveStates::crossCov(long id) const
{
    const Block& b = block(id);
    return cross_.middleRows(static_cast<Eigen::Index>(b.row), b.dim);
}

Eigen::MatrixXd PassiveStates::crossCov(long id, size_t first, int cols) const
{
    const Block& b = block(id);
    if (cols < 0 || first + static_cast<size_t>(cols) > static_cast<size_t>(cross_.cols()))
        throw std::out_of_range("PassiveStates::crossCov: columns out of range");
    return cross_.block(static_cast<Eigen::Index>(b.row), static_cast<Eigen::Index>(first), b.dim, cols);
}

size_t PassiveStates::storedCovarianceEntries() const
{
    size_t n = static_cast<size_t>(cross_.size());
    for (const auto& o : own_) n += static_cast<size_t>(o.size());
    return n;
}

void PassiveStates::predictVehicle(const Eigen::Matrix3d& F)
{
    if (blocks_.empty()) return;
    cross_.leftCols<3>() = (cross_.leftCols<3>() * F.transpose()).eval();
}

void PassiveStates::predictVehicle(const Eigen::Matrix3d& F, Eigen::Index param, const Eigen::Vector3d& G)
{
    if (blocks_.empty()) return;
    cross_.leftCols<3>() = (cross_.leftCols<3>() * F.transpose() + cross_.col(param) * G.transpose()).eval();
}

void PassiveStates::copyActiveColumns(size_t from, size_t to, size_t dim)
{
    if (blocks_.empty()) return;
    const auto d = static_cast<Eigen::Index>(dim);
    cross_.middleCols(static_cast<Eigen::Index>(to), d) = cross_.middleCols(static_cast<Eigen::Index>(from), d).eval();
}

void PassiveStates::applyUpdate(
    const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_a, const Eigen::VectorXd& y)
{
    applyMeanUpdate(W_p, y);
    applyCovarianceUpdate(W_p, W_a);
}

void PassiveStates::applyMeanUpdate(const Eigen::MatrixXd& W_p, const Eigen::VectorXd& y)
{
    if (blocks_.empty()) return;
    mean_.noalias() += W_p * y;
}

void PassiveStates::applyCovarianceUpdate(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_a)
{
    if (blocks_.empty()) return;
    cross_.noalias() -= W_p * W_a.transpose();
    for (size_t k = 0; k < blocks_.size(); ++k)
    {
        const auto Wb = W_p.middleRows(static_cast<Eigen::Index>(blocks_[k].row), blocks_[k].dim);
        own_[k].noalias() -= Wb * Wb.transpose();
        own_[k] = (0.5 * (own_[k] + own_[k].transpose())).eval();
    }
}

void PassiveStates::invariantRetraction(const Eigen::VectorXd& before, const Eigen::Matrix2d& V,
                                        const Eigen::VectorXd& b_a, const Eigen::VectorXd& c_a, double sigma)
{
    if (blocks_.empty()) return;
    Eigen::VectorXd b_p = Eigen::VectorXd::Zero(mean_.size());
    for (const Block& blk : blocks_)
        if (blk.dim >= 2) detail::retractPosition(mean_, before, V, static_cast<Eigen::Index>(blk.row), b_p);
    // The joint M P M^T: the passive rows of c = P e read before the cross terms move.
    const Eigen::VectorXd c_p = cross_.col(2);
    for (size_t k = 0; k < blocks_.size(); ++k)
    {
        const auto r = static_cast<Eigen::Index>(blocks_[k].row);
        const Eigen::Index d = blocks_[k].dim;
        const Eigen::VectorXd bk = b_p.segment(r, d), ck = c_p.segment(r, d);
        own_[k] += bk * ck.transpose() + ck * bk.transpose() + sigma * bk * bk.transpose();
        own_[k] = (0.5 * (own_[k] + own_[k].transpose())).eval();
    }
    cross_ += b_p * c_a.transpose() + c_p * b_a.transpose() + sigma * b_p * b_a.transpose();
}

void PassiveStates::appendActiveColumns(const Eigen::MatrixXd& new_cols)
{
    if (blocks_.empty()) return;
    const Eigen::Index c = cross_.cols();
    cross_.conservativeResize(Eigen::NoChange, c + new_cols.cols());
    cross_.rightCols(new_cols.cols()) = new_cols;
}

void PassiveStates::blendActiveColumns(size_t a, size_t l, size_t dim, double rho)
{
    if (blocks_.empty()) return;
    const auto d = static_cast<Eigen::Index>(dim);
    cross_.middleCols(static_cast<Eigen::Index>(a), d) =
        rho * cross_.middleCols(static_cast<Eigen::Index>(a), d) +
        (1 - rho) * cross_.middleCols(static_cast<Eigen::Index>(l), d);
}

void PassiveStates::removeActiveColumns(size_t offset, size_t dim)
{
    if (blocks_.empty()) return;
    const auto o = static_cast<Eigen::Index>(offset), d = static_cast<Eigen::Index>(dim);
    const Eigen::Index tail = cross_.cols() - o - d;
    if (tail > 0) cross_.middleCols(o, tail) = cross_.rightCols(tail).eval();
    cross_.conservativeResize(Eigen::NoChange, cross_.cols() - d);
}

void PassiveStates::clear()
{
    blocks_.clear();
    index_.clear();
    mean_.resize(0);
    cross_.resize(0, 0);
    own_.clear();
}

}  // namespace hymm::ekf
