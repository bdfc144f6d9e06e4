/**
 * @file StateLayout.h
 * @brief Bookkeeping of the EKF state vector: the vehicle pose block followed by
 *        landmark blocks of different sizes (2-DOF points, 3-DOF poses, ...).
 *
 * The state is x = [x_v ; x_m1 ; x_m2 ; ...] (thesis Eq. 2.2 / 2.12). Each landmark
 * block has a stable integer ID that never changes while it lives, a dimension and
 * an offset into the state. Removing a block shifts the offsets of the blocks after
 * it; IDs stay valid. The layout only records where things are: the numbers live in
 * the filter that owns the layout.
 */
#pragma once

#include <cstddef>
#include <unordered_map>
#include <vector>

namespace mrpt::serialization
{
class CArchive;
}

namespace hymm::ekf
{
/** Where one landmark lives in the state, plus its track bookkeeping. */
struct LandmarkBlock
{
    long id = -1;          //!< stable identifier, >= 0
    int dim = 2;           //!< number of state entries (2: point, 3: pose)
    size_t offset = 0;     //!< index of the first entry in the state vector
    int times_seen = 0;    //!< observations used so far (creation counts as one)
    long created_step = 0; //!< update step in which the block was created
    bool confirmed = false;//!< true once seen often enough (tentative before)
    /** A helper state of another block (EkfSlam::addBlockCopy), not a landmark of the
     *  map: EkfSlam::landmarkIds() and numLandmarks() leave it out. */
    bool auxiliary = false;
};

class StateLayout
{
public:
    static constexpr int kVehicleDim = 3;  //!< (x, y, phi)

    /** Total state size: vehicle plus every landmark block. */
    size_t size() const { return size_; }
    size_t numLandmarks() const { return blocks_.size(); }

    /** Appends a block at the end of the state; throws if `id` < 0, is already used or
     *  `dim` < 1. Returns the new block. */
    const LandmarkBlock& add(long id, int dim, long created_step);

    /** Removes the block with `id` and shifts later offsets; throws if unknown. Returns
     *  the removed block (with its old offset), so the caller can delete its rows. */
    LandmarkBlock remove(long id);

    bool has(long id) const { return index_.count(id) != 0; }
    /** Throws std::out_of_range naming the id if it is unknown. */
    const LandmarkBlock& get(long id) const;
    LandmarkBlock& get(long id);

    /** Blocks in state order. */
    const std::vector<LandmarkBlock>& blocks() const { return blocks_; }
    std::vector<LandmarkBlock>& blocks() { return blocks_; }
    std::vector<long> ids() const;

    /** Ids from here up are reserved for blocks the pipeline adds for itself (the turn
     *  bias, a vehicle copy): far from any id a dataset or an automatic id would use. */
    static constexpr long kFirstReservedId = 1L << 60;

    /** Smallest id larger than any id ever added below kFirstReservedId (automatic ids
     *  never collide). */
    long nextFreeId() const { return next_free_id_; }

    /** Saved run state (hymm-slam --save-state): every member a later step reads, bit
     *  for bit; loadState() replaces them (options come from the config). Throws
     *  std::runtime_error on a corrupt or truncated state. Source: EkfSlamState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

    void clear();

private:
    std::vector<LandmarkBlock> blocks_;
    std::unordered_map<long, size_t> index_;  //!< id -> position in blocks_
    size_t size_ = kVehicleDim;
    long next_free_id_ = 0;
};

}  // namespace hymm::ekf
