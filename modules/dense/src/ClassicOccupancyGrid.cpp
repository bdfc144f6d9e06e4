#include "hymm/dense/ClassicOccupancyGrid.h"

#include "hymm/dense/geometry.h"

#include <hymm/core/config_utils.h>

namespace hymm::dense
{
hymm::core::OptionTable ClassicOccupancyGrid::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("x_min_m", x_min_m, "m", between(-1e5, 1e5), "predefined map area (cell size from `[OccupancyLayer]`)");
    t.real("x_max_m", x_max_m, "m", between(-1e5, 1e5), "predefined map area (> x_min_m)");
    t.real("y_min_m", y_min_m, "m", between(-1e5, 1e5), "predefined map area");
    t.real("y_max_m", y_max_m, "m", between(-1e5, 1e5), "predefined map area (> y_min_m)");
    t.real("max_range_m", max_range_m, "m", above(0, 1000), "returns beyond are free space only");
    return t;
}

void ClassicOccupancyGrid::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void ClassicOccupancyGrid::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void ClassicOccupancyGrid::Options::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    if (!(x_max_m > x_min_m)) throwConfigError(s, "x_max_m", std::to_string(x_max_m), "must be > x_min_m");
    if (!(y_max_m > y_min_m)) throwConfigError(s, "y_max_m", std::to_string(y_max_m), "must be > y_min_m");
    if (!(max_range_m > 0)) throwConfigError(s, "max_range_m", std::to_string(max_range_m), "must be > 0");
}

ClassicOccupancyGrid::ClassicOccupancyGrid(const Options& options, const OccupancyLayer::Options& model)
    : options_(options),
      model_(model),
      grid_(LogOddsGrid::covering(
          {options.x_min_m, options.y_min_m}, {options.x_max_m, options.y_max_m}, model.cell_size_m,
          model.priorLogOdds()))
{
    options_.validate();
    model_.validate();
}

void ClassicOccupancyGrid::insertScan(const ScanPoints& scan, const mrpt::math::TPose2D& vehicle_pose)
{
    const WorldScan w = scan.toWorld(vehicle_pose, options_.max_range_m);
    const Eigen::Vector2d lo = grid_.origin();
    const Eigen::Vector2d hi = lo + grid_.cellSize() * Eigen::Vector2d(grid_.sizeX(), grid_.sizeY());
    for (const WorldBeam& b : w.beams)
    {
        // Clip to the predefined area so that the traversal stays bounded.
        const auto iv = clipSegmentToBox(w.sensor, b.end, lo, hi);
        if (!iv) continue;
        const Eigen::Vector2d d = b.end - w.sensor;
        const bool to_end = iv->t1 >= 1.0;
        grid_.markFree(w.sensor + iv->t0 * d, to_end ? b.end : Eigen::Vector2d(w.sensor + iv->t1 * d), b.hit && to_end);
        if (b.hit && to_end) grid_.markOccupied(b.end);
    }
    grid_.applyMarks(
        model_.missIncrement(), model_.hitIncrement(), model_.clampMinLogOdds(), model_.clampMaxLogOdds());
}

double ClassicOccupancyGrid::probabilityAt(const Eigen::Vector2d& p) const
{
    int ix, iy;
    if (!grid_.cellOf(p, ix, iy)) return logistic(grid_.initialLogOdds());
    return logistic(grid_.logOdds(ix, iy));
}

void ClassicOccupancyGrid::toOccupancyGridMap(mrpt::maps::COccupancyGridMap2D& out) const
{
    const Eigen::Vector2d lo = grid_.origin();
    const double c = grid_.cellSize();
    out.setSize(
        static_cast<float>(lo.x()), static_cast<float>(lo.x() + c * grid_.sizeX()),
        static_cast<float>(lo.y()), static_cast<float>(lo.y() + c * grid_.sizeY()),
        static_cast<float>(c), 0.5f);
    // Sample at cell centres: robust to MRPT rounding its own size.
    for (unsigned cy = 0; cy < out.getSizeY(); ++cy)
        for (unsigned cx = 0; cx < out.getSizeX(); ++cx)
            out.setCell(
                static_cast<int>(cx), static_cast<int>(cy),
                static_cast<float>(probabilityAt({out.idx2x(cx), out.idx2y(cy)})));
}

}  // namespace hymm::dense
