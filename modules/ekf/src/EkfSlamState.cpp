// The filter's state for a saved run (hymm-slam --save-state / --resume): everything an
// update or prediction reads, written bit for bit so that a resumed run continues exactly
// as the uninterrupted one (core/state_archive.h).
#include "hymm/ekf/EkfSlam.h"

#include <hymm/core/state_archive.h>

#include <algorithm>

namespace hymm::ekf
{
using namespace hymm::core::state;

void StateLayout::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "StateLayout");
    writeSize(out, blocks_.size());
    for (const LandmarkBlock& b : blocks_)
    {
        writeLong(out, b.id);
        out << static_cast<std::int32_t>(b.dim) << static_cast<std::uint64_t>(b.offset)
            << static_cast<std::int32_t>(b.times_seen);
        writeLong(out, b.created_step);
        out << b.confirmed << b.auxiliary;
    }
    out << static_cast<std::uint64_t>(size_);
    writeLong(out, next_free_id_);
}

void StateLayout::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "StateLayout");
    std::vector<LandmarkBlock> blocks(readSize(in, "landmark block"));
    std::unordered_map<long, size_t> index;
    for (size_t i = 0; i < blocks.size(); ++i)
    {
        LandmarkBlock& b = blocks[i];
        std::int32_t dim = 0, seen = 0;
        b.id = readLong(in);
        in >> dim;
        b.offset = readU64(in);
        in >> seen;
        b.dim = dim;
        b.times_seen = seen;
        b.created_step = readLong(in);
        b.confirmed = readBool(in);
        b.auxiliary = readBool(in);
        if (b.id < 0 || dim < 1 || !index.emplace(b.id, i).second)
            throw std::runtime_error("corrupt state: landmark block " + std::to_string(i));
    }
    const size_t size = readU64(in);
    const long next = readLong(in);
    blocks_ = std::move(blocks);
    index_ = std::move(index);
    size_ = size;
    next_free_id_ = next;
}

void PassiveStates::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "PassiveStates");
    writeSize(out, blocks_.size());
    for (const Block& b : blocks_)
    {
        writeLong(out, b.id);
        out << static_cast<std::int32_t>(b.dim) << static_cast<std::uint64_t>(b.row);
    }
    writeMatrix(out, mean_);
    writeMatrix(out, cross_);
    for (const Eigen::MatrixXd& c : own_) writeMatrix(out, c);
}

void PassiveStates::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "PassiveStates");
    std::vector<Block> blocks(readSize(in, "passive block"));
    std::unordered_map<long, size_t> index;
    for (size_t i = 0; i < blocks.size(); ++i)
    {
        std::int32_t dim = 0;
        blocks[i].id = readLong(in);
        in >> dim;
        blocks[i].dim = dim;
        blocks[i].row = readU64(in);
        if (dim < 1 || !index.emplace(blocks[i].id, i).second)
            throw std::runtime_error("corrupt state: passive block " + std::to_string(i));
    }
    Eigen::VectorXd mean;
    Eigen::MatrixXd cross;
    readMatrix(in, mean, "passive mean");
    readMatrix(in, cross, "passive cross-covariance");
    std::vector<Eigen::MatrixXd> own(blocks.size());
    for (Eigen::MatrixXd& c : own) readMatrix(in, c, "passive covariance");
    blocks_ = std::move(blocks);
    index_ = std::move(index);
    mean_ = std::move(mean);
    cross_ = std::move(cross);
    own_ = std::move(own);
}

void EkfSlam::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "EkfSlam");
    layout_.saveState(out);
    writeMatrix(out, x_);
    // The whole storage, spare room included: the covariance blocks then keep the
    // same strides, hence the same floating-point operations, after a resume.
    writeMatrix(out, Pbuf_);
    passive_.saveState(out);
    // First estimates in state order (a hash map's order is not part of the state).
    writeSize(out, first_estimates_.size());
    std::vector<long> ids;
    for (const auto& kv : first_estimates_) ids.push_back(kv.first);
    std::sort(ids.begin(), ids.end());
    for (long id : ids)
    {
        writeLong(out, id);
        writeMatrix(out, first_estimates_.at(id));
    }
    writeMatrix(out, predicted_pose_);
    writeMatrix(out, last_F_);
    writeLong(out, step_);
}

void EkfSlam::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "EkfSlam");
    layout_.loadState(in);
    readMatrix(in, x_, "EKF mean");
    readMatrix(in, Pbuf_, "EKF covariance");
    if (Pbuf_.rows() < x_.size() || Pbuf_.rows() != Pbuf_.cols() ||
        static_cast<size_t>(x_.size()) != layout_.size())
        throw std::runtime_error("corrupt state: EKF mean and covariance sizes disagree");
    passive_.loadState(in);
    first_estimates_.clear();
    const size_t n = readSize(in, "first estimate");
    for (size_t i = 0; i < n; ++i)
    {
        const long id = readLong(in);
        readMatrix(in, first_estimates_[id], "first estimate");
    }
    readMatrix(in, predicted_pose_, "predicted pose");
    readMatrix(in, last_F_, "motion Jacobian");
    step_ = readLong(in);
}

}  // namespace hymm::ekf
