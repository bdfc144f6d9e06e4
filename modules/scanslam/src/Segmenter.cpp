/**
 * @file Segmenter.cpp
 * @brief Distance-criterion segmentation (thesis 5.2.2, 5.7).
 */
#include "hymm/scanslam/Segmenter.h"

#include <cmath>
#include <stdexcept>

#include "hymm/core/config_utils.h"

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

void Segmenter::Options::load(const mrpt::config::CConfigFileBase& cfg,
                              const std::string& section)
{
    using namespace hymm::core;
    checkKnownKeys(cfg, section,
                   {"min_points", "max_range_gap_m", "max_angle_gap_deg", "max_range_m"});
    const long n = readInt(cfg, section, "min_points", static_cast<long>(min_points));
    if (n < 2) throwConfigError(section, "min_points", std::to_string(n), "must be >= 2");
    min_points = static_cast<size_t>(n);
    max_range_gap_m = readDoubleMin(cfg, section, "max_range_gap_m", max_range_gap_m, 0, true);
    max_angle_gap = M_PI / 180 *
                    readDoubleMin(cfg, section, "max_angle_gap_deg", max_angle_gap * 180 / M_PI,
                                  0, true);
    max_range_m = readDoubleMin(cfg, section, "max_range_m", max_range_m, 0, false);
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
