/**
 * @file LogOddsGrid.h
 * @brief Uniform occupancy grid in log-odds with per-scan beam marking (thesis 2.8.1, 4.1).
 *
 * Storage and update rule shared by the per-region OccupancyLayer and the classic
 * global baseline (ClassicOccupancyGrid), so both use exactly the same sensor model.
 *
 * Update (thesis Eq. 4.7, corrected). Bayes' rule for the binary cell state with the
 * observations r^{k+1} = {r^k, r_{k+1}}, assuming r_{k+1} independent of r^k given the
 * cell state, gives in log-odds l(x) = log(x / (1 - x)):
 *   l(C_i | r^{k+1}) = l(C_i | r^k) + l(C_i | r_{k+1}) - l(C_i)
 * where l(C_i | r_{k+1}) is the inverse sensor model for the newest reading alone and
 * l(C_i) the prior. The printed Eq. 4.7 repeats l(C_i | r^k) in its second term, which
 * would double-count the history; a test checks that one hit on a prior of 0.3 yields
 * exactly the inverse-model probability, as the corrected rule requires.
 *
 * Each cell changes at most once per scan: beams first mark cells free/occupied and
 * applyMarks() then adds one increment per marked cell, occupied winning over free
 * (a grazing neighbouring beam must not erase the cell its neighbour hit). Cells can
 * be excluded from updates with setUpdatable(false); the OccupancyLayer uses this to
 * keep updates inside its triangle.
 */
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <iosfwd>
#include <vector>

namespace mrpt::serialization
{
class CArchive;
}

namespace hymm::dense
{
class LogOddsGrid
{
public:
    /** Grid of size_x * size_y square cells of `cell_size` [m], lower-left corner at
     *  `origin`, all cells at log-odds `initial` and updatable. */
    LogOddsGrid(const Eigen::Vector2d& origin, int size_x, int size_y, double cell_size, float initial);
    /** Smallest grid of `cell_size` covering the box [lo, hi]. */
    static LogOddsGrid covering(
        const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double cell_size, float initial);

    int sizeX() const { return size_x_; }
    int sizeY() const { return size_y_; }
    double cellSize() const { return cell_size_; }
    const Eigen::Vector2d& origin() const { return origin_; }
    float initialLogOdds() const { return initial_; }

    /** Cell holding `p`; false if outside the grid. */
    bool cellOf(const Eigen::Vector2d& p, int& ix, int& iy) const;
    Eigen::Vector2d cellCentre(int ix, int iy) const;
    Eigen::Vector2d cellMin(int ix, int iy) const;
    float logOdds(int ix, int iy) const { return l_[index(ix, iy)]; }
    void setLogOdds(int ix, int iy, float l) { l_[index(ix, iy)] = l; }
    bool updatable(int ix, int iy) const { return (flags_[index(ix, iy)] & kUpdatable) != 0; }
    void setUpdatable(int ix, int iy, bool on);

    /** Marks as free the cells crossed by segment [from, to] (Amanatides-Woo
     *  traversal), leaving out the cell holding `to` when `exclude_end_cell`. */
    void markFree(const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool exclude_end_cell);
    /** Marks as occupied the cell holding `p` (ignored outside the grid). */
    void markOccupied(const Eigen::Vector2d& p);
    /** Adds `l_occ` to every cell marked occupied and `l_free` to every other marked
     *  cell, clamps to [l_min, l_max], clears the marks. Returns the cells updated. */
    size_t applyMarks(float l_free, float l_occ, float l_min, float l_max);

    /** Cells whose value differs from the initial one. */
    size_t changedCells() const;
    size_t memoryBytes() const;

    void save(std::ostream& out) const;
    /** Throws std::runtime_error on malformed input. */
    static LogOddsGrid load(std::istream& in);
    /** Saved run state (hymm-slam --save-state): every member a later step reads, bit
     *  for bit; loadState() replaces them (options come from the config). Throws
     *  std::runtime_error on a corrupt or truncated state. Source: DenseLayerState.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

private:
    static constexpr std::uint8_t kUpdatable = 1;
    static constexpr std::uint8_t kFree = 2;
    static constexpr std::uint8_t kOccupied = 4;

    size_t index(int ix, int iy) const
    {
        return static_cast<size_t>(iy) * static_cast<size_t>(size_x_) + static_cast<size_t>(ix);
    }
    void mark(int ix, int iy, std::uint8_t bit);

    Eigen::Vector2d origin_;
    int size_x_;
    int size_y_;
    double cell_size_;
    float initial_;
    std::vector<float> l_;
    std::vector<std::uint8_t> flags_;
    std::vector<size_t> touched_;  //!< marked cells of the scan in progress
};

/** log(p / (1 - p)). */
inline double logit(double p) { return std::log(p / (1.0 - p)); }
/** Inverse of logit. */
inline double logistic(double l) { return 1.0 / (1.0 + std::exp(-l)); }

}  // namespace hymm::dense
