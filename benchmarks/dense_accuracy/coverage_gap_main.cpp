/**
 * @file coverage_gap_main.cpp
 * @brief Why the HYMM occupancy layer misses outline the classic grid of the same run
 *        covers (issue: the dense map must keep what the laser saw).
 *
 * Runs hymm-slam's pipeline on a simulated rawlog, samples the true object outlines as the
 * outline metrics do (every 5 cm, covered within 0.3 m) and takes the samples the classic
 * grid covers (cells with P > 0.8) but the HYMM occupancy layer does not. Each is put in
 * the first class that holds it:
 *  - beyond_dense_range: no return placed at the TRUE pose came within 0.3 m of it from
 *    closer than [HybridMetricMap] max_range_m (the classic grid's range is larger);
 *  - points_cover: the HYMM points layer covers it (the returns reached the dense map;
 *    the occupancy cells there stay at or below P = 0.8);
 *  - points_displaced: the points layer has a point within 1 m but not within 0.3 m
 *    (the returns are there, carried off by the map error);
 *  - lost: seen in range, no HYMM point within 1 m (returns dropped or never fused).
 *
 *   hymm-coverage-gap -c slam.ini -r run.rawlog --gt-path P.tum --gt-objects O.txt
 */
#include <hymm/app/slam_outputs.h>
#include <hymm/core/config_utils.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/eval/laser_coverage.h>
#include <hymm/io/RawlogReader.h>
#include <hymm/io/trajectory_io.h>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <fstream>
#include <iostream>
#include <limits>
#include <stdexcept>

namespace
{
using V2 = Eigen::Vector2d;
constexpr double kOccupied = 0.8;   //!< occupied cells for the outline metrics (as hymm-slam)
constexpr double kNearMiss = 1.0;   //!< [m] a point this close is the return, displaced

void addScan(const mrpt::obs::CObservation::Ptr& o, std::vector<hymm::eval::TimedScan>& scans)
{
    if (const auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o))
        scans.push_back({mrpt::Clock::toDouble(s->timestamp), hymm::dense::ScanPoints::fromRangeScan(*s)});
}

/** Highest P(occupied) of the cells of `g` within `r` of `q` (0 off the grid). */
double maxNear(const mrpt::maps::COccupancyGridMap2D& g, const V2& q, double r)
{
    double best = 0;
    if (g.getSizeX() == 0) return best;
    const double step = g.getResolution() / 2;
    for (double dx = -r; dx <= r; dx += step)
        for (double dy = -r; dy <= r; dy += step)
        {
            if (dx * dx + dy * dy > r * r) continue;
            const int cx = g.x2idx(q.x() + dx), cy = g.y2idx(q.y() + dy);
            if (cx >= 0 && cy >= 0 && cx < static_cast<int>(g.getSizeX()) && cy < static_cast<int>(g.getSizeY()))
                best = std::max(best, static_cast<double>(g.getCell(cx, cy)));
        }
    return best;
}

std::vector<char> coveredBy(const hymm::eval::SeenOutline& seen, const std::vector<V2>& pts, double r)
{
    hymm::eval::SeenOutline s = seen;
    s.radius_m = r;
    return hymm::eval::coverageOfSeen(s, pts).covered;
}

int run(int argc, char** argv)
{
    TCLAP::CmdLine cmd("hymm-coverage-gap: why HYMM occupancy misses what the classic grid covers", ' ', "0.1");
    TCLAP::ValueArg<std::string> config("c", "config", "hymm-slam .ini", true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> rawlog("r", "rawlog", "simulated rawlog", true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> gtp("", "gt-path", "true path (TUM)", true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> gto("", "gt-objects", "true object outlines", true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> samples_out(
        "", "samples", "write one line per gap sample the points cover: x y region(-1 = none) "
        "max_P_regions max_P_tiles max_P_map (within the coverage radius)", false, "", "FILE", cmd);
    if (!cmd.parse(argc, argv)) return 0;

    const auto cfg = hymm::core::openConfigFile(config.getValue());
    auto slam = hymm::denseslam::DenseSlam::fromConfig(*cfg);
    if (!slam.options().denseLayer("points") || !slam.hybridMap()->options().enable_occupancy || !slam.classicGrid())
        throw std::invalid_argument("the config must enable the points and occupancy layers and the classic grid");
    std::vector<hymm::eval::TimedScan> scans;
    hymm::io::RawlogReader reader(rawlog.getValue());
    hymm::io::RawlogEntry e;
    while (reader.next(e))
    {
        if (e.frame)
            for (const auto& o : *e.frame) addScan(o, scans);
        if (e.observation) addScan(e.observation, scans);
        slam.processEntry(e);
    }
    slam.refreshRegions();

    const auto& hybrid = *slam.hybridMap();
    mrpt::maps::COccupancyGridMap2D occ, classic;
    hybrid.renderOccupancy(*slam.partition(), hybrid.options().occupancy.cell_size_m, occ);
    slam.classicGrid()->toOccupancyGridMap(classic);
    mrpt::maps::COccupancyGridMap2D occ_reg, occ_fb;
    hybrid.renderOccupancy(*slam.partition(), hybrid.options().occupancy.cell_size_m, occ_reg,
                           hymm::dense::HybridMetricMap::Content::Regions);
    if (hybrid.options().fallback_max_distance_m > 0)
        hybrid.renderOccupancy(*slam.partition(), hybrid.options().occupancy.cell_size_m, occ_fb,
                               hymm::dense::HybridMetricMap::Content::Fallback);
    mrpt::maps::CSimplePointsMap pts_map;
    hybrid.renderPoints(*slam.partition(), pts_map);
    const auto occ_pts = hymm::dense::occupiedCellCentres(occ, kOccupied);
    const auto classic_pts = hymm::dense::occupiedCellCentres(classic, kOccupied);
    const auto points = hymm::dense::pointsOf(pts_map);

    const auto path = hymm::io::readTum(gtp.getValue());
    const auto outlines = hymm::app::loadObjectOutlines(gto.getValue());
    hymm::eval::LaserCoverageOptions lo;
    lo.max_range_m = hybrid.options().max_range_m;
    const auto seen_dense = hymm::eval::laserSeenOutline(scans, path, outlines, lo);

    const auto c_classic = coveredBy(seen_dense, classic_pts, lo.radius_m);
    const auto c_occ = coveredBy(seen_dense, occ_pts, lo.radius_m);
    const auto c_pts = coveredBy(seen_dense, points, lo.radius_m);
    const auto c_pts_near = coveredBy(seen_dense, points, kNearMiss);
    std::ofstream samples_file;
    if (samples_out.isSet())
    {
        samples_file.open(samples_out.getValue());
        if (!samples_file) throw std::runtime_error("cannot write " + samples_out.getValue());
    }
    size_t pc_hist[2][3] = {};
    size_t hidden_by_region = 0, split = 0, weak_region_only = 0, weak_fallback_only = 0;
    size_t classic_n = 0, occ_n = 0, gap = 0, beyond = 0, pcover = 0, displaced = 0, lost = 0;
    for (size_t i = 0; i < c_classic.size(); ++i)
    {
        classic_n += c_classic[i] != 0;
        occ_n += c_occ[i] != 0;
        if (!c_classic[i] || c_occ[i]) continue;
        ++gap;
        if (!seen_dense.seen[i]) ++beyond;
        else if (c_pts[i])
        {
            ++pcover;
            const V2 q = seen_dense.samples.points[i];
            const double best = maxNear(occ, q, lo.radius_m);
            const double reg = maxNear(occ_reg, q, lo.radius_m), fb = maxNear(occ_fb, q, lo.radius_m);
            const auto region = slam.partition()->findRegion(q);
            const bool in_region = region.has_value();
            if (samples_file.is_open())
                samples_file << q.x() << ' ' << q.y() << ' ' << (region ? *region : -1L) << ' ' << reg << ' ' << fb
                             << ' ' << best << '\n';
            // Evidence split: the regions and the tiles each hold some of it.
            if (fb > kOccupied) ++hidden_by_region;
            else if (reg > 0.51 && fb > 0.51) ++split;
            else if (reg > 0.51) ++weak_region_only;
            else if (fb > 0.51) ++weak_fallback_only;
            ++pc_hist[in_region][best < 0.49 ? 0 : best <= 0.51 ? 1 : 2];
        }
        else if (c_pts_near[i]) ++displaced;
        else ++lost;
    }
    const double n = static_cast<double>(c_classic.size());
    std::cout << "samples " << c_classic.size() << " classic " << classic_n / n << " occupancy " << occ_n / n
              << " ratio " << (classic_n ? static_cast<double>(occ_n) / classic_n : 0.0) << "\n"
              << "gap " << gap << " beyond_dense_range " << beyond << " points_cover " << pcover
              << " points_displaced " << displaced << " lost " << lost << "\n"
              << "points_cover max P within radius (free / unknown / (0.5, 0.8]): in a region " << pc_hist[1][0]
              << " / " << pc_hist[1][1] << " / " << pc_hist[1][2] << ", in no region " << pc_hist[0][0] << " / "
              << pc_hist[0][1] << " / " << pc_hist[0][2] << "\n"
              << "points_cover: fallback > 0.8 under a region " << hidden_by_region << ", evidence in regions and tiles "
              << split << ", weak in regions only " << weak_region_only << ", weak in tiles only " << weak_fallback_only
              << "\n";
    return 0;
}
}  // namespace

int main(int argc, char** argv)
{
    try
    {
        return run(argc, argv);
    }
    catch (const std::exception& ex)
    {
        std::cerr << "hymm-coverage-gap: " << ex.what() << "\n";
        return 1;
    }
}
