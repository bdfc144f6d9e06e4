/**
 * @file Segmenter.h
 * @brief Scan segmentation by the distance criterion (thesis 5.2.2, 5.7): consecutive
 *        returns are neighbours when their ranges differ by less than a range gap and
 *        their bearings by less than an angle gap; a run of neighbours with at least a
 *        minimum number of points is a segment.
 *
 * Ini section (default [ScanSegmentation]); key table in the module README. The
 * thesis' real-data values (100 points, 5 m, 3 deg) are Options::thesisRealData().
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <mrpt/config/CConfigFileBase.h>

#include <string>
#include <vector>

#include "hymm/scanslam/PointSet.h"

namespace hymm::scanslam
{
class Segmenter
{
public:
    struct Options
    {
        size_t min_points = 20;             //!< fewest points in a segment
        double max_range_gap_m = 0.5;       //!< neighbours: |r_i - r_j| below this [m]
        double max_angle_gap = 3 * M_PI / 180;  //!< and bearings closer than this [rad]
        double max_range_m = 0;             //!< ignore returns beyond this (0: keep all)

        /** Thesis 5.7, car park: 100 points, 5 m, 3 deg. */
        static Options thesisRealData();

        /** Every key, declared once (loader, unknown-key check, saver, README table). */
        core::OptionTable table();
        /** Reads [section]; unknown keys and bad values throw naming the key. */
        void load(const mrpt::config::CConfigFileBase& cfg, const std::string& section);
        void save(mrpt::config::CConfigFileBase& cfg, const std::string& section) const;
    };

    /** Indices into a PointSet, in scan order. */
    using Segment = std::vector<size_t>;

    explicit Segmenter(const Options& options) : options_(options) {}

    /** Segments of `scan` (a PointSet from fromScan(): range and bearing set). Runs
     *  shorter than min_points are dropped and counted in `short_runs`. */
    std::vector<Segment> segment(const PointSet& scan, size_t* short_runs = nullptr) const;

    const Options& options() const { return options_; }

private:
    Options options_;
};

}  // namespace hymm::scanslam
