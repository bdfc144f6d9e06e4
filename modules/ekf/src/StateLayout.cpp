#include "hymm/ekf/StateLayout.h"

#include <stdexcept>
#include <string>

namespace hymm::ekf
{
const LandmarkBlock& StateLayout::add(long id, int dim, long created_step)
{
    if (id < 0) throw std::invalid_argument("StateLayout::add: negative landmark id");
    if (dim < 1) throw std::invalid_argument("StateLayout::add: block dimension must be >= 1");
    if (has(id))
        throw std::invalid_argument("StateLayout::add: landmark id " + std::to_string(id) +
                                    " already exists");
    LandmarkBlock b;
    b.id = id;
    b.dim = dim;
    b.offset = size_;
    b.created_step = created_step;
    index_[id] = blocks_.size();
    blocks_.push_back(b);
    size_ += static_cast<size_t>(dim);
    // Reserved ids (the filter's own auxiliary blocks) leave the automatic ids as they were.
    if (id >= next_free_id_ && id < kFirstReservedId) next_free_id_ = id + 1;
    return blocks_.back();
}

LandmarkBlock StateLayout::remove(long id)
{
    const auto it = index_.find(id);
    if (it == index_.end())
        throw std::out_of_range("StateLayout::remove: unknown landmark id " + std::to_string(id));
    const size_t pos = it->second;
    const LandmarkBlock removed = blocks_[pos];
    blocks_.erase(blocks_.begin() + static_cast<std::ptrdiff_t>(pos));
    index_.erase(it);
    for (size_t k = pos; k < blocks_.size(); ++k)
    {
        blocks_[k].offset -= static_cast<size_t>(removed.dim);
        index_[blocks_[k].id] = k;
    }
    size_ -= static_cast<size_t>(removed.dim);
    return removed;
}

const LandmarkBlock& StateLayout::get(long id) const
{
    const auto it = index_.find(id);
    if (it == index_.end())
        throw std::out_of_range("EKF state: unknown landmark id " + std::to_string(id));
    return blocks_[it->second];
}

LandmarkBlock& StateLayout::get(long id)
{
    return const_cast<LandmarkBlock&>(static_cast<const StateLayout&>(*this).get(id));
}

std::vector<long> StateLayout::ids() const
{
    std::vector<long> out;
    out.reserve(blocks_.size());
    for (const auto& b : blocks_) out.push_back(b.id);
    return out;
}

void StateLayout::clear()
{
    blocks_.clear();
    index_.clear();
    size_ = kVehicleDim;
    next_free_id_ = 0;
}

}  // namespace hymm::ekf
