/**
 * @file EkfSlamAuxiliary.cpp
 * @brief Auxiliary blocks: a copy of a block plus independent noise, and one step of a
 *        first-order Gauss-Markov process of a block about another (e.g. the apparent
 *        pose of a scan template about its pose, scanslam::ScanLandmarkMap).
 */
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <string>

#include "check_covariance.h"
#include "hymm/ekf/EkfSlam.h"

namespace hymm::ekf
{
using detail::checkCovariance;

long EkfSlam::addBlockCopy(long src, const Eigen::MatrixXd& noise_cov, long id)
{
    const LandmarkBlock s = layout_.get(src);  // a copy: the layout grows below
    const auto o = static_cast<Eigen::Index>(s.offset), d = static_cast<Eigen::Index>(s.dim);
    checkCovariance(noise_cov, d, "EkfSlam::addBlockCopy(noise_cov)");
    if (id < 0) id = layout_.nextFreeId();
    if (layout_.has(id))
        throw std::invalid_argument("EkfSlam::addBlockCopy: id " + std::to_string(id) + " exists");
    // The augmentation x_new = x_src + w (Eq. 2.53 with the source block in the vehicle's
    // place and G = I): rows P_src,*, diagonal block P_src,src + noise.
    const Eigen::MatrixXd cross = activeP().middleRows(o, d);  // d x n
    const Eigen::MatrixXd passive_cols =
        passive_.numBlocks() > 0 ? Eigen::MatrixXd(passive_.crossAll().middleCols(o, d)) : Eigen::MatrixXd();
    appendBlocks({{id, x_.segment(o, d)}}, cross, cross.middleCols(o, d) + noise_cov, passive_cols, true);
    layout_.get(id).auxiliary = true;
    const auto fe = first_estimates_.find(src);
    if (fe != first_estimates_.end()) first_estimates_[id] = Eigen::VectorXd(fe->second);
    return id;
}

long EkfSlam::addAuxiliaryBlock(const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov, long id)
{
    const auto d = mean.size();
    if (d == 0 || !mean.allFinite()) throw std::invalid_argument("EkfSlam::addAuxiliaryBlock: empty or non-finite mean");
    checkCovariance(cov, d, "EkfSlam::addAuxiliaryBlock(cov)");
    if (id < 0) id = layout_.nextFreeId();
    if (layout_.has(id))
        throw std::invalid_argument("EkfSlam::addAuxiliaryBlock: id " + std::to_string(id) + " exists");
    const Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(d, x_.size());
    const Eigen::MatrixXd passive_cols =
        passive_.numBlocks() > 0 ? Eigen::MatrixXd::Zero(passive_.crossAll().rows(), d) : Eigen::MatrixXd();
    appendBlocks({{id, mean}}, cross, cov, passive_cols, true);
    layout_.get(id).auxiliary = true;
    return id;
}

long EkfSlam::addVehicleCopy(long id)
{
    if (id < 0) id = layout_.nextFreeId();
    if (layout_.has(id))
        throw std::invalid_argument("EkfSlam::addVehicleCopy: id " + std::to_string(id) + " exists");
    // Eq. 2.53 with G_v = I and no noise: rows P_v*, diagonal block P_vv.
    const Eigen::MatrixXd cross = activeP().topRows<3>();
    const Eigen::MatrixXd passive_cols =
        passive_.numBlocks() > 0 ? Eigen::MatrixXd(passive_.crossAll().leftCols<3>()) : Eigen::MatrixXd();
    appendBlocks({{id, x_.head<3>()}}, cross, cross.leftCols<3>(), passive_cols, true);
    layout_.get(id).auxiliary = true;
    return id;
}

void EkfSlam::recopyVehicle(long copy)
{
    const LandmarkBlock& b = layout_.get(copy);
    if (b.dim != 3) throw std::invalid_argument("EkfSlam::recopyVehicle: block " + std::to_string(copy) + " is not 3-DOF");
    const auto o = static_cast<Eigen::Index>(b.offset);
    x_.segment<3>(o) = x_.head<3>();
    // Rows first, then columns: after the rows, the copy's columns in the vehicle rows
    // hold P_vv already, so the column pass reads no stale entry. O(n).
    auto P = activeP();
    P.middleRows<3>(o) = P.topRows<3>();
    P.middleCols<3>(o) = P.leftCols<3>();
    passive_.copyActiveColumns(0, b.offset, 3);
    first_estimates_[copy] = x_.head<3>();
}

void EkfSlam::relaxBlockTowards(long a, long l, double rho, const Eigen::MatrixXd& Q)
{
    const LandmarkBlock& ba = layout_.get(a);
    const LandmarkBlock& bl = layout_.get(l);
    if (a == l || ba.dim != bl.dim)
        throw std::invalid_argument("EkfSlam::relaxBlockTowards: blocks must differ and have the same dimension");
    if (!(rho >= 0 && rho <= 1)) throw std::invalid_argument("EkfSlam::relaxBlockTowards: rho outside [0, 1]");
    const auto oa = static_cast<Eigen::Index>(ba.offset), ol = static_cast<Eigen::Index>(bl.offset),
               d = static_cast<Eigen::Index>(ba.dim);
    checkCovariance(Q, d, "EkfSlam::relaxBlockTowards(Q)");
    Eigen::VectorXd diff = x_.segment(oa, d) - x_.segment(ol, d);
    if (d == 3) diff[2] = mrpt::math::wrapToPi(diff[2]);
    x_.segment(oa, d) = x_.segment(ol, d) + rho * diff;
    if (d == 3) x_[oa + 2] = mrpt::math::wrapToPi(x_[oa + 2]);
    // T P T^T in place: rows a first, then columns a of the result (row l and column l are
    // unchanged by T, so neither pass reads an entry it already wrote elsewhere). O(n).
    auto P = activeP();
    P.middleRows(oa, d) = rho * P.middleRows(oa, d) + (1 - rho) * P.middleRows(ol, d);
    P.middleCols(oa, d) = rho * P.middleCols(oa, d) + (1 - rho) * P.middleCols(ol, d);
    const Eigen::MatrixXd Paa = P.block(oa, oa, d, d) + Q;
    P.block(oa, oa, d, d) = 0.5 * (Paa + Paa.transpose());
    passive_.blendActiveColumns(ba.offset, bl.offset, ba.dim, rho);
}

size_t EkfSlam::numLandmarks() const
{
    const auto& blocks = layout_.blocks();
    return static_cast<size_t>(std::count_if(blocks.begin(), blocks.end(),
                                             [](const LandmarkBlock& b) { return !b.auxiliary; }));
}

std::vector<long> EkfSlam::landmarkIds() const
{
    std::vector<long> out;
    out.reserve(layout_.numLandmarks());
    for (const LandmarkBlock& b : layout_.blocks())
        if (!b.auxiliary) out.push_back(b.id);
    return out;
}

}  // namespace hymm::ekf
