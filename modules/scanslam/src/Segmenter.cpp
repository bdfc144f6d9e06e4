/**
 * @file Segmenter.cpp
 * @brief Distance-criterion segmentation (thesis 5.2.2, 5.7).
 */
#include "hymm/scanslam/Segmenter.h"

#include <cmath>
#include <stdexcept>

namespace hymm::scanslam
{
Segmenter::Options Segmenter::Options::thesisRealData()
{
    Options o;
    o.min_points = 100;
    o.max_range_gap_m = 5.0;
    o.max_angle_gap = 3 * M_PI / 180;
    return o;
}

core::OptionTable Segmenter::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.integer("min_points", min_points, "", 2, 1000000, "fewest points in a segment");
    t.real("max_range_gap_m", max_range_gap_m, "m", above(0, 1000), "neighbours differ in range by less than this");
    t.real("max_angle_gap_deg", max_angle_gap, "deg", above(0, 180), "and in bearing by less than this", M_PI / 180);
    t.real("max_range_m", max_range_m, "m", atLeast(0, 10000),
           "returns beyond this end a segment and are ignored (0: none)");
    return t;
}

void Segmenter::Options::load(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    table().load(cfg, section);
}

void Segmenter::Options::save(mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    auto copy = *this;
    copy.table().save(cfg, section);
}

std::vector<Segmenter::Segment> Segmenter::segment(const PointSet& scan, size_t* short_runs) const
{
    if (scan.range.size() != scan.size() || scan.bearing.size() != scan.size())
        throw std::invalid_argument("Segmenter::segment: the point set has no range/bearing");
    std::vector<Segment> out;
    size_t dropped = 0;
    Segment run;
    const auto close_run = [&]() {
        if (run.size() >= options_.min_points)
            out.push_back(run);
        else if (!run.empty())
            ++dropped;
        run.clear();
    };
    for (size_t i = 0; i < scan.size(); ++i)
    {
        if (options_.max_range_m > 0 && scan.range[i] > options_.max_range_m)
        {
            close_run();
            continue;
        }
        if (!run.empty())
        {
            const size_t j = run.back();
            const bool neighbour =
                std::abs(scan.range[i] - scan.range[j]) < options_.max_range_gap_m &&
                std::abs(scan.bearing[i] - scan.bearing[j]) < options_.max_angle_gap;
            if (!neighbour) close_run();
        }
        run.push_back(i);
    }
    close_run();
    if (short_runs) *short_runs = dropped;
    return out;
}

}  // namespace hymm::scanslam
